// Ed25519 verification: the scalar checks and reduction modulo L, then [S]B - [k]A by one
// interleaved double-and-add pass, compared with R (RFC 8032 §5.1.7, cofactorless).
#include "palpa/protocol/ed25519.h"

#include "ed25519_point.h"
#include "palpa/protocol/sha512.h"

namespace palpa::protocol {
namespace {

using ed25519::Point;

/// The group order L = 2^252 + 27742317777372353535851937790883648493, little-endian words.
constexpr uint32_t kOrder[8] = {0x5cf5d3ed, 0x5812631a, 0xa2f79cd6, 0x14def9de,
                                0x00000000, 0x00000000, 0x00000000, 0x10000000};

using Scalar = uint32_t[8];

void LoadWords(Scalar out, const uint8_t* in) {
  for (int i = 0; i < 8; ++i) {
    out[i] = static_cast<uint32_t>(in[4 * i]) | static_cast<uint32_t>(in[4 * i + 1]) << 8 |
             static_cast<uint32_t>(in[4 * i + 2]) << 16 |
             static_cast<uint32_t>(in[4 * i + 3]) << 24;
  }
}

bool BelowOrder(const Scalar s) {
  for (int i = 7; i >= 0; --i) {
    if (s[i] != kOrder[i]) return s[i] < kOrder[i];
  }
  return false;  // equal to L
}

/// A 512-bit little-endian number modulo L, a bit at a time from the top: r = 2r + bit, less L
/// when it reaches L. Some 20 000 instructions, against the million of the point arithmetic.
void ReduceModOrder(Scalar out, const uint8_t in[64]) {
  for (int i = 0; i < 8; ++i) out[i] = 0;
  for (int bit = 511; bit >= 0; --bit) {
    for (int i = 7; i > 0; --i) out[i] = out[i] << 1 | out[i - 1] >> 31;  // r < L < 2^253
    out[0] = out[0] << 1 | ((in[bit / 8] >> (bit % 8)) & 1u);
    if (BelowOrder(out)) continue;
    uint32_t borrow = 0;
    for (int i = 0; i < 8; ++i) {
      const uint64_t d = uint64_t{out[i]} - kOrder[i] - borrow;
      out[i] = static_cast<uint32_t>(d);
      borrow = static_cast<uint32_t>(d >> 63);
    }
  }
}

bool Bit(const Scalar s, int i) { return ((s[i / 32] >> (i % 32)) & 1u) != 0; }

/// [s]B + [k]P, both scalars below L < 2^253, sharing one chain of doublings (Straus).
void DoubleScalarMul(Point& out, const Scalar s, const Scalar k, const Point& p,
                     VerifyProgress* progress) {
  Point base_plus_p;
  ed25519::AddPoints(base_plus_p, ed25519::kBase, p);
  out = ed25519::kIdentity;
  bool started = false;
  for (int i = 252; i >= 0; --i) {
    if (started) ed25519::DoublePoint(out, out);
    const bool sb = Bit(s, i), kb = Bit(k, i);
    if (sb && kb) {
      ed25519::AddPoints(out, out, base_plus_p);
    } else if (sb) {
      ed25519::AddPoints(out, out, ed25519::kBase);
    } else if (kb) {
      ed25519::AddPoints(out, out, p);
    }
    started = started || sb || kb;
    if (progress != nullptr && i % 32 == 0) progress->Step();
  }
}

}  // namespace

const char* SignatureCheckName(SignatureCheck c) {
  switch (c) {
    case SignatureCheck::kValid:
      return "valid";
    case SignatureCheck::kBadLength:
      return "signature or key of the wrong length";
    case SignatureCheck::kNonCanonicalS:
      return "S not below the group order (non-canonical)";
    case SignatureCheck::kBadKey:
      return "public key not a canonical curve point";
    case SignatureCheck::kSmallOrderKey:
      return "public key of small order";
    case SignatureCheck::kBadR:
      return "R not a canonical curve point";
    case SignatureCheck::kSmallOrderR:
      return "R of small order";
    case SignatureCheck::kMismatch:
      return "signature does not match the message and key";
  }
  return "?";
}

SignatureCheck Ed25519Verify(const uint8_t* signature, size_t signature_size,
                             const uint8_t* message, size_t message_size, const uint8_t* public_key,
                             size_t public_key_size, VerifyProgress* progress) {
  auto step = [progress] {
    if (progress != nullptr) progress->Step();
  };
  if (signature_size != kEd25519SignatureSize || public_key_size != kEd25519PublicKeySize)
    return SignatureCheck::kBadLength;
  const uint8_t* r_bytes = signature;
  Scalar s;
  LoadWords(s, signature + 32);
  if (!BelowOrder(s)) return SignatureCheck::kNonCanonicalS;
  Point a;
  if (ed25519::DecodePoint(a, public_key) != ed25519::Decoded::kOk) return SignatureCheck::kBadKey;
  step();
  if (ed25519::HasSmallOrder(a)) return SignatureCheck::kSmallOrderKey;
  Point r;
  if (ed25519::DecodePoint(r, r_bytes) != ed25519::Decoded::kOk) return SignatureCheck::kBadR;
  step();
  if (ed25519::HasSmallOrder(r)) return SignatureCheck::kSmallOrderR;

  Sha512Hasher hasher;
  hasher.Update(r_bytes, 32);
  hasher.Update(public_key, 32);
  hasher.Update(message, message_size);
  const Sha512Digest h = hasher.Finish();
  Scalar k;
  ReduceModOrder(k, h.data());

  Point minus_a, check;
  ed25519::NegatePoint(minus_a, a);
  DoubleScalarMul(check, s, k, minus_a, progress);
  uint8_t encoded[32];
  ed25519::EncodePoint(encoded, check);
  step();
  uint8_t differ = 0;
  for (int i = 0; i < 32; ++i) differ |= static_cast<uint8_t>(encoded[i] ^ r_bytes[i]);
  return differ == 0 ? SignatureCheck::kValid : SignatureCheck::kMismatch;
}

}  // namespace palpa::protocol
