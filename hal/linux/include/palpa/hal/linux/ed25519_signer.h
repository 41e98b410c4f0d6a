// Ed25519 signing of firmware images on Linux, with libsodium: `palpa package --sign` and
// palpa-sim's factory image. The board only ever verifies (protocol/ed25519.h).
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/image.h"

namespace palpa::hal::linux_signing {

using Ed25519Seed = std::array<uint8_t, 32>;  ///< a private key: what a key file holds
using Ed25519Key = std::array<uint8_t, 32>;   ///< a public key

/// A key pair that signs images (libsodium's crypto_sign_detached over the image's SHA-256).
class Ed25519Signer final : public protocol::ImageSigner {
 public:
  explicit Ed25519Signer(const Ed25519Seed& seed);
  /// A fresh key pair from the system's randomness (libsodium's randombytes).
  static Ed25519Signer Generate();
  Ed25519Signer(const Ed25519Signer&) = default;
  Ed25519Signer& operator=(const Ed25519Signer&) = default;
  ~Ed25519Signer();

  const uint8_t* PublicKey() const override { return public_.data(); }
  bool Sign(const protocol::Sha256Digest& digest, uint8_t* signature) override;
  const Ed25519Key& public_key() const { return public_; }
  const Ed25519Seed& seed() const { return seed_; }

 private:
  Ed25519Seed seed_{};
  std::array<uint8_t, 64> secret_{};  ///< libsodium's form: the seed, then the public key
  Ed25519Key public_{};
};

}  // namespace palpa::hal::linux_signing
