// The CRC-32 slicing tables and their word and byte steps, shared by the CRC and the frame encoder.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

namespace palpa::protocol {

static_assert(std::endian::native == std::endian::little,
              "the word-wise CRC reads four packet bytes as one little-endian word");

/// kCrc32Tables[0] is the classic byte table; [k] advances a byte's contribution k more bytes.
using Crc32Tables = std::array<std::array<uint32_t, 256>, 4>;
/// Hidden: one module's data, addressed PC-relative even in position-independent builds.
extern const Crc32Tables kCrc32Tables __attribute__((visibility("hidden")));

/// The four tables held in four registers, for a loop over words: each lookup is then one load
/// (a shared base would cost an extra address add for three of the four).
struct Crc32Bases {
  const uint32_t* t0 = kCrc32Tables[0].data();
  const uint32_t* t1 = kCrc32Tables[1].data();
  const uint32_t* t2 = kCrc32Tables[2].data();
  const uint32_t* t3 = kCrc32Tables[3].data();

  Crc32Bases() {
    // Hides that the bases are one array apart, so the compiler keeps four registers.
    asm("" : "+r"(t1), "+r"(t2), "+r"(t3));
  }
  /// Advances the (inverted) CRC register over four bytes loaded as one little-endian word.
  uint32_t Word(uint32_t c, uint32_t word) const {
    c ^= word;
    return t3[c & 0xFFu] ^ t2[(c >> 8) & 0xFFu] ^ t1[(c >> 16) & 0xFFu] ^ t0[c >> 24];
  }
};

/// Advances the (inverted) CRC register over one byte.
inline uint32_t Crc32Byte(uint32_t c, uint8_t byte) {
  return (c >> 8) ^ kCrc32Tables[0][(c ^ byte) & 0xFFu];
}

}  // namespace palpa::protocol
