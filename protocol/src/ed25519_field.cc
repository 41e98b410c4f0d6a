// Field arithmetic modulo 2^255 - 19 on eight 32-bit words, reduced with 2^256 ≡ 38 (mod p).
#include "ed25519_field.h"

namespace palpa::protocol::ed25519 {
namespace {

/// lo:hi = a·b + lo + hi, which never overflows 64 bits: one UMAAL on a core with the DSP
/// extension (the Cortex-M4), whose multiply-accumulate loops GCC does not find by itself.
inline void MulAdd(uint32_t& lo, uint32_t& hi, uint32_t a, uint32_t b) {
#if defined(__ARM_FEATURE_DSP)
  asm("umaal %0, %1, %2, %3" : "+r"(lo), "+r"(hi) : "r"(a), "r"(b));
#else
  const uint64_t x = uint64_t{a} * b + lo + hi;
  lo = static_cast<uint32_t>(x);
  hi = static_cast<uint32_t>(x >> 32);
#endif
}

/// Brings `out` + carry·2^256 below 2^256 again: the carry comes back in as carry·38. A second
/// wrap past 2^256 leaves a value below 38·2, so the loop ends after two rounds at most.
void Fold(Fe& out, uint64_t carry) {
  while (carry != 0) {
    uint64_t t = carry * 38;
    for (int i = 0; i < 8 && t != 0; ++i) {
      t += out.w[i];
      out.w[i] = static_cast<uint32_t>(t);
      t >>= 32;
    }
    carry = t;
  }
}

/// A 512-bit product reduced below 2^256: the high half comes back in times 38.
void Reduce(Fe& out, const uint32_t t[16]) {
  uint32_t carry = 0;
#pragma GCC unroll 8
  for (int i = 0; i < 8; ++i) {
    uint32_t lo = t[i];
    MulAdd(lo, carry, t[i + 8], 38);
    out.w[i] = lo;
  }
  Fold(out, carry);
}

/// z^(2^250 - 1) into *high and z^11 into *z11: the common start of the two long powers.
void Pow2250(Fe& high, Fe& z11, const Fe& z) {
  Fe t0, t1, t2;
  Square(t0, z);           // z^2
  SquareTimes(t1, t0, 2);  // z^8
  Mul(t1, t1, z);          // z^9
  Mul(z11, t0, t1);        // z^11
  Square(t0, z11);         // z^22
  Mul(t0, t0, t1);         // z^(2^5 - 1)
  SquareTimes(t1, t0, 5);
  Mul(t0, t1, t0);  // z^(2^10 - 1)
  SquareTimes(t1, t0, 10);
  Mul(t1, t1, t0);  // z^(2^20 - 1)
  SquareTimes(t2, t1, 20);
  Mul(t1, t2, t1);  // z^(2^40 - 1)
  SquareTimes(t1, t1, 10);
  Mul(t0, t1, t0);  // z^(2^50 - 1)
  SquareTimes(t1, t0, 50);
  Mul(t1, t1, t0);  // z^(2^100 - 1)
  SquareTimes(t2, t1, 100);
  Mul(t1, t2, t1);  // z^(2^200 - 1)
  SquareTimes(t1, t1, 50);
  Mul(high, t1, t0);  // z^(2^250 - 1)
}

}  // namespace

void Add(Fe& out, const Fe& a, const Fe& b) {
  uint64_t carry = 0;
  for (int i = 0; i < 8; ++i) {
    carry += uint64_t{a.w[i]} + b.w[i];
    out.w[i] = static_cast<uint32_t>(carry);
    carry >>= 32;
  }
  Fold(out, carry);
}

void Sub(Fe& out, const Fe& a, const Fe& b) {
  uint32_t borrow = 0;
  for (int i = 0; i < 8; ++i) {
    const uint64_t d = uint64_t{a.w[i]} - b.w[i] - borrow;
    out.w[i] = static_cast<uint32_t>(d);
    borrow = static_cast<uint32_t>(d >> 63);
  }
  // Below zero the words hold the result + 2^256, and 2^256 ≡ 38: take 38 off (twice at most).
  while (borrow != 0) {
    uint32_t take = 38;
    for (int i = 0; i < 8 && take != 0; ++i) {
      const uint64_t d = uint64_t{out.w[i]} - take;
      out.w[i] = static_cast<uint32_t>(d);
      take = static_cast<uint32_t>(d >> 63);
    }
    borrow = take;
  }
}

void Mul(Fe& out, const Fe& a, const Fe& b) {
  uint32_t t[16] = {};
#pragma GCC unroll 8
  for (int i = 0; i < 8; ++i) {
    uint32_t carry = 0;
#pragma GCC unroll 8
    for (int j = 0; j < 8; ++j) MulAdd(t[i + j], carry, a.w[i], b.w[j]);
    t[i + 8] = carry;
  }
  Reduce(out, t);
}

void Square(Fe& out, const Fe& a) {
  // The cross products once, doubled, then the squares on the diagonal.
  uint32_t t[16] = {};
#pragma GCC unroll 7
  for (int i = 0; i < 7; ++i) {
    uint32_t carry = 0;
#pragma GCC unroll 7
    for (int j = i + 1; j < 8; ++j) MulAdd(t[i + j], carry, a.w[i], a.w[j]);
    t[i + 8] = carry;
  }
  uint32_t top = 0;
  for (int i = 0; i < 16; ++i) {
    const uint32_t next = t[i] >> 31;
    t[i] = t[i] << 1 | top;
    top = next;
  }
  uint64_t carry = 0;
  for (int i = 0; i < 8; ++i) {
    const uint64_t sq = uint64_t{a.w[i]} * a.w[i];
    carry += uint64_t{t[2 * i]} + static_cast<uint32_t>(sq);
    t[2 * i] = static_cast<uint32_t>(carry);
    carry >>= 32;
    carry += uint64_t{t[2 * i + 1]} + (sq >> 32);
    t[2 * i + 1] = static_cast<uint32_t>(carry);
    carry >>= 32;
  }
  Reduce(out, t);
}

void SquareTimes(Fe& out, const Fe& a, int n) {
  Square(out, a);
  for (int i = 1; i < n; ++i) Square(out, out);
}

void Invert(Fe& out, const Fe& a) {
  Fe high, z11;
  Pow2250(high, z11, a);
  SquareTimes(high, high, 5);
  Mul(out, high, z11);  // z^(2^255 - 32 + 11) = z^(p - 2)
}

void Pow2523(Fe& out, const Fe& a) {
  Fe high, z11;
  Pow2250(high, z11, a);
  SquareTimes(high, high, 2);
  Mul(out, high, a);  // z^(2^252 - 4 + 1) = z^((p - 5)/8)
}

Fe Canonical(const Fe& a) {
  Fe r = a;
  for (int round = 0; round < 2; ++round) {  // bit 255 comes back as 19 (2^255 ≡ 19)
    uint64_t carry = uint64_t{r.w[7] >> 31} * 19;
    r.w[7] &= 0x7fffffffu;
    for (int i = 0; i < 8; ++i) {
      carry += r.w[i];
      r.w[i] = static_cast<uint32_t>(carry);
      carry >>= 32;
    }
  }
  // Now r < 2^255, and r ≥ p exactly when r + 19 reaches 2^255; then r - p = r + 19 - 2^255.
  Fe s;
  uint64_t carry = 19;
  for (int i = 0; i < 8; ++i) {
    carry += r.w[i];
    s.w[i] = static_cast<uint32_t>(carry);
    carry >>= 32;
  }
  if ((s.w[7] >> 31) == 0) return r;
  s.w[7] &= 0x7fffffffu;
  return s;
}

bool IsZero(const Fe& a) {
  const Fe c = Canonical(a);
  uint32_t any = 0;
  for (uint32_t w : c.w) any |= w;
  return any == 0;
}

bool Equal(const Fe& a, const Fe& b) {
  Fe d;
  Sub(d, a, b);
  return IsZero(d);
}

bool IsNegative(const Fe& a) { return (Canonical(a).w[0] & 1) != 0; }

void ToBytes(uint8_t out[32], const Fe& a) {
  const Fe c = Canonical(a);
  for (int i = 0; i < 32; ++i) out[i] = static_cast<uint8_t>(c.w[i / 4] >> (8 * (i % 4)));
}

bool FromBytes(Fe& out, const uint8_t in[32]) {
  for (int i = 0; i < 8; ++i) {
    out.w[i] = static_cast<uint32_t>(in[4 * i]) | static_cast<uint32_t>(in[4 * i + 1]) << 8 |
               static_cast<uint32_t>(in[4 * i + 2]) << 16 |
               static_cast<uint32_t>(in[4 * i + 3]) << 24;
  }
  out.w[7] &= 0x7fffffffu;  // bit 255 is the sign of x, not part of y
  const Fe c = Canonical(out);
  for (int i = 0; i < 8; ++i) {
    if (c.w[i] != out.w[i]) return false;  // y ≥ p
  }
  return true;
}

}  // namespace palpa::protocol::ed25519
