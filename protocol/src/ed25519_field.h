// Arithmetic modulo p = 2^255 - 19 for the Ed25519 verifier: eight 32-bit words, kept below 2^256
// (not always below p) between operations, made canonical only to compare or encode. Variable
// time: it only ever handles public values (keys, signatures, messages).
#pragma once

#include <cstdint>

namespace palpa::protocol::ed25519 {

/// A field element, little-endian 32-bit words; any value below 2^256 stands for itself mod p.
struct Fe {
  uint32_t w[8];
};

inline constexpr Fe kZero{{0, 0, 0, 0, 0, 0, 0, 0}};
inline constexpr Fe kOne{{1, 0, 0, 0, 0, 0, 0, 0}};
/// d = -121665/121666, the curve constant, and 2d (the addition formula's).
inline constexpr Fe kD{{0x135978a3, 0x75eb4dca, 0x4141d8ab, 0x00700a4d, 0x7779e898, 0x8cc74079,
                        0x2b6ffe73, 0x52036cee}};
inline constexpr Fe kD2{{0x26b2f159, 0xebd69b94, 0x8283b156, 0x00e0149a, 0xeef3d130, 0x198e80f2,
                         0x56dffce7, 0x2406d9dc}};
/// A square root of -1: 2^((p-1)/4).
inline constexpr Fe kSqrtM1{{0x4a0ea0b0, 0xc4ee1b27, 0xad2fe478, 0x2f431806, 0x3dfbd7a7, 0x2b4d0099,
                             0x4fc1df0b, 0x2b832480}};

void Add(Fe& out, const Fe& a, const Fe& b);
void Sub(Fe& out, const Fe& a, const Fe& b);
void Mul(Fe& out, const Fe& a, const Fe& b);
void Square(Fe& out, const Fe& a);
/// a^(2^n): n squarings.
void SquareTimes(Fe& out, const Fe& a, int n);
/// 1/a (a^(p-2)); 0 for 0.
void Invert(Fe& out, const Fe& a);
/// a^((p-5)/8), the square-root candidate's power.
void Pow2523(Fe& out, const Fe& a);

/// The value in [0, p).
Fe Canonical(const Fe& a);
bool IsZero(const Fe& a);
bool Equal(const Fe& a, const Fe& b);
/// The low bit of the canonical value: RFC 8032's sign of x.
bool IsNegative(const Fe& a);

/// 32 bytes, little-endian, canonical (the top bit clear).
void ToBytes(uint8_t out[32], const Fe& a);
/// The low 255 bits of 32 bytes; false when they are p or more (a non-canonical encoding).
bool FromBytes(Fe& out, const uint8_t in[32]);

}  // namespace palpa::protocol::ed25519
