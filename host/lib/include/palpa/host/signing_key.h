// Signing keys for firmware images on the host: key files read and written (`palpa keygen`,
// `palpa package --sign`) and the key id `palpa flash` names a package's signer by. The signing
// itself is libsodium's (hal/linux/ed25519_signer.h); the board only verifies.
#pragma once

#include <string>

#include "palpa/hal/linux/ed25519_signer.h"
#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"

namespace palpa::host {

using hal::linux_signing::Ed25519Key;
using hal::linux_signing::Ed25519Seed;
using hal::linux_signing::Ed25519Signer;

inline constexpr FileLimits kKeyFileLimits{"key file", 4096};

/// A key's id: the first 8 bytes of the SHA-256 of the public key, in hex (16 digits).
std::string KeyId(const uint8_t* public_key);

/// A private key file: '#' comment lines and one line of 64 hexadecimal digits (the 32-byte
/// seed, which an Ed25519Signer is made from). invalid_argument naming the file and what is wrong.
Result<Ed25519Seed> ReadSigningKey(const std::string& path);
/// A public key file, in the same form.
Result<Ed25519Key> ReadPublicKey(const std::string& path);

/// A fresh key pair written to `private_path` (created with mode 0600; refused, and nothing
/// written, when it or `private_path`.pub exists) and `private_path`.pub; its key id.
Result<std::string> WriteKeyPair(const std::string& private_path);

}  // namespace palpa::host
