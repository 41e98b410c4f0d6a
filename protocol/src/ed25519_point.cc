// Point decoding, encoding, addition and doubling on edwards25519 (RFC 8032 §5.1.3-§5.1.4).
#include "ed25519_point.h"

namespace palpa::protocol::ed25519 {

Decoded DecodePoint(Point& out, const uint8_t in[32]) {
  Fe y;
  if (!FromBytes(y, in)) return Decoded::kNonCanonical;
  const bool sign = (in[31] >> 7) != 0;
  // x^2 = u/v with u = y^2 - 1, v = d y^2 + 1; the candidate x = u v^3 (u v^7)^((p-5)/8).
  Fe y2, u, v, v3, uv7, x, vx2;
  Square(y2, y);
  Sub(u, y2, kOne);
  Mul(v, y2, kD);
  Add(v, v, kOne);
  Square(v3, v);
  Mul(v3, v3, v);  // v^3
  Square(uv7, v3);
  Mul(uv7, uv7, v);
  Mul(uv7, uv7, u);  // u v^7
  Pow2523(x, uv7);
  Mul(x, x, v3);
  Mul(x, x, u);
  Square(vx2, x);
  Mul(vx2, vx2, v);
  if (!Equal(vx2, u)) {
    Fe minus_u;
    Sub(minus_u, kZero, u);
    if (!Equal(vx2, minus_u)) return Decoded::kNotOnCurve;
    Mul(x, x, kSqrtM1);
  }
  if (IsZero(x) && sign) return Decoded::kNonCanonical;
  if (IsNegative(x) != sign) Sub(x, kZero, x);
  out.x = x;
  out.y = y;
  out.z = kOne;
  Mul(out.t, x, y);
  return Decoded::kOk;
}

void EncodePoint(uint8_t out[32], const Point& p) {
  Fe zinv, x, y;
  Invert(zinv, p.z);
  Mul(x, p.x, zinv);
  Mul(y, p.y, zinv);
  ToBytes(out, y);
  if (IsNegative(x)) out[31] |= 0x80;
}

void AddPoints(Point& out, const Point& a, const Point& b) {
  // add-2008-hwcd-3 for a = -1: 8 multiplications and one by 2d.
  Fe ta, tb, c, d, e, f, g, h;
  Sub(ta, a.y, a.x);
  Sub(tb, b.y, b.x);
  Mul(ta, ta, tb);  // A
  Add(tb, a.y, a.x);
  Add(c, b.y, b.x);
  Mul(tb, tb, c);  // B
  Mul(c, a.t, b.t);
  Mul(c, c, kD2);  // C
  Mul(d, a.z, b.z);
  Add(d, d, d);  // D
  Sub(e, tb, ta);
  Sub(f, d, c);
  Add(g, d, c);
  Add(h, tb, ta);
  Mul(out.x, e, f);
  Mul(out.y, g, h);
  Mul(out.t, e, h);
  Mul(out.z, f, g);
}

void DoublePoint(Point& out, const Point& a) {
  // dbl-2008-hwcd for a = -1: 4 multiplications and 4 squarings.
  Fe ta, tb, c, h, e, g, f;
  Square(ta, a.x);
  Square(tb, a.y);
  Square(c, a.z);
  Add(c, c, c);
  Add(h, ta, tb);
  Add(e, a.x, a.y);
  Square(e, e);
  Sub(e, h, e);
  Sub(g, ta, tb);
  Add(f, c, g);
  Mul(out.x, e, f);
  Mul(out.y, g, h);
  Mul(out.t, e, h);
  Mul(out.z, f, g);
}

void NegatePoint(Point& out, const Point& a) {
  Sub(out.x, kZero, a.x);
  out.y = a.y;
  out.z = a.z;
  Sub(out.t, kZero, a.t);
}

bool HasSmallOrder(const Point& p) {
  Point q;
  DoublePoint(q, p);
  DoublePoint(q, q);
  DoublePoint(q, q);
  return IsZero(q.x) && Equal(q.y, q.z);
}

}  // namespace palpa::protocol::ed25519
