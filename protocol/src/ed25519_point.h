// Points of edwards25519 (-x^2 + y^2 = 1 + d x^2 y^2) in extended coordinates (X:Y:Z:T),
// x = X/Z, y = Y/Z, xy = T/Z (Hisil, Wong, Carter, Dawson 2008; RFC 8032 §5.1.4). Variable time:
// the verifier's points are all public.
#pragma once

#include <cstdint>

#include "ed25519_field.h"

namespace palpa::protocol::ed25519 {

struct Point {
  Fe x, y, z, t;
};

/// The neutral element (0, 1).
inline constexpr Point kIdentity{kZero, kOne, kOne, kZero};
/// The base point B (y = 4/5, x even).
inline constexpr Point kBase{{{0x8f25d51a, 0xc9562d60, 0x9525a7b2, 0x692cc760, 0xfdd6dc5c,
                               0xc0a4e231, 0xcd6e53fe, 0x216936d3}},
                             {{0x66666658, 0x66666666, 0x66666666, 0x66666666, 0x66666666,
                               0x66666666, 0x66666666, 0x66666666}},
                             kOne,
                             {{0xa5b7dda3, 0x6dde8ab3, 0x775152f5, 0x20f09f80, 0x64abe37d,
                               0x66ea4e8e, 0xd78b7665, 0x67875f0f}}};

enum class Decoded : uint8_t {
  kOk,
  kNonCanonical,  ///< y ≥ p, or x = 0 with the sign bit set
  kNotOnCurve,    ///< no x satisfies the curve equation for this y
};

/// RFC 8032 §5.1.3, strict: a non-canonical y or a "negative zero" x is refused.
Decoded DecodePoint(Point& out, const uint8_t in[32]);
/// The canonical encoding: y, with the sign of x in bit 255.
void EncodePoint(uint8_t out[32], const Point& p);

void AddPoints(Point& out, const Point& a, const Point& b);
void DoublePoint(Point& out, const Point& a);
void NegatePoint(Point& out, const Point& a);
/// [8]P is the neutral element: P is one of the eight points of order 1, 2, 4 or 8.
bool HasSmallOrder(const Point& p);

}  // namespace palpa::protocol::ed25519
