// Ed25519 signature verification (RFC 8032 §5.1.7), freestanding: the board's check of a firmware
// image's signature, in the bootloader and the update engine alike. Signing is the host's
// (libsodium); the board only ever verifies.
//
// Constant time: verification handles no secret — the public key, the message and the signature
// are all public, and a signature's validity is what the caller learns anyway — so this code
// branches and indexes on its inputs freely and makes no constant-time claim. It must never be
// reused for anything holding a secret scalar (signing, key exchange).
//
// Acceptance rules, chosen to be at least as strict as libsodium's crypto_sign_verify_detached
// (1.0.18, its default build): S must be below the group order L; the public key A must be a
// canonical encoding (y < p, and no "negative zero" x) of a curve point that is not of small
// order; R must be a canonical encoding of a curve point that is not of small order; and the
// equation is the cofactorless one, encode([S]B - [k]A) == R bytes, k = SHA-512(R || A || M) mod
// L. libsodium rejects small-order R and A by a list of their encodings, here by [8]P == O: the
// same set of points, so both accept exactly the same signatures (tests/protocol/ed25519_test.cc
// holds that against libsodium).
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::protocol {

inline constexpr size_t kEd25519PublicKeySize = 32;
inline constexpr size_t kEd25519SignatureSize = 64;

/// Called now and then during a verification (after each point decoding and every 32 bits of
/// the scalars, at most some 300 000 instructions apart on a Cortex-M4): where a board kicks its
/// watchdog, since a whole verification outlasts its period on a slow core.
class VerifyProgress {
 public:
  virtual void Step() = 0;

 protected:
  ~VerifyProgress() = default;
};

/// The verdict, with the reason a signature is refused.
enum class SignatureCheck : uint8_t {
  kValid,
  kBadLength,      ///< signature not 64 bytes or key not 32
  kNonCanonicalS,  ///< S ≥ L (a malleated signature)
  kBadKey,         ///< A not a canonical encoding of a curve point
  kSmallOrderKey,  ///< A of order 1, 2, 4 or 8 (such a key verifies forged signatures)
  kBadR,           ///< R not a canonical encoding of a curve point
  kSmallOrderR,    ///< R of small order
  kMismatch,       ///< well-formed, but not a signature of this message by this key
};
const char* SignatureCheckName(SignatureCheck c);

SignatureCheck Ed25519Verify(const uint8_t* signature, size_t signature_size,
                             const uint8_t* message, size_t message_size, const uint8_t* public_key,
                             size_t public_key_size, VerifyProgress* progress = nullptr);

}  // namespace palpa::protocol
