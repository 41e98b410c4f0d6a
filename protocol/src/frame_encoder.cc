// Fused CRC-32 + COBS frame encoder: one load per four packet bytes, zero bytes found a word at a
// time, so telemetry framing stays within its instruction budget on a Cortex-M4.
#include "frame_encoder.h"

#include <array>

#include "crc32_tables.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {
namespace {

// COBS state: `code_at` is the pending code byte of the open block, `dst` the next free byte;
// the block length (code byte included) is dst - code_at.
struct CobsCursor {
  uint8_t* code_at;
  uint8_t* dst;

  // Ends the open block at `zero_at`, where a zero byte was (speculatively) copied: that byte
  // becomes the next block's code byte.
  void CloseAt(uint8_t* zero_at) {
    *code_at = static_cast<uint8_t>(zero_at - code_at);
    code_at = zero_at;
  }

  // Byte-at-a-time COBS for the tail and for long zero-free runs (254-byte blocks).
  void Bytes(const uint8_t* in, const uint8_t* end) {
    while (in != end) {
      const uint8_t byte = *in++;
      if (byte == 0) {
        *code_at = static_cast<uint8_t>(dst - code_at);
        code_at = dst++;
        continue;
      }
      *dst++ = byte;
      if (dst - code_at == 0xFF) {  // a full block: 254 data bytes
        *code_at = 0xFF;
        if (in == end) return;  // a full block ends the input: no further code byte
        code_at = dst++;
      }
    }
    *code_at = static_cast<uint8_t>(dst - code_at);
  }
};

// Bit 7 of each zero byte of `word`, exactly (no borrow between bytes).
inline uint32_t ZeroBytes(uint32_t word) {
  return ~(((word & 0x7F7F7F7Fu) + 0x7F7F7F7Fu) | word) & 0x80808080u;
}

// Which of the four bytes are zero, as bits 0..3 (bit k: the k-th byte in memory). One multiply
// gathers bits 7, 15, 23, 31 into 28..31 without carries.
inline uint32_t ZeroPattern(uint32_t zero_bytes) { return (zero_bytes * 0x00204081u) >> 28; }

// What a word with zero bytes in a given pattern does to the COBS output, found once per pattern
// instead of zero by zero: every zero but the last becomes the code byte of a block that ends
// inside the word (its length is the distance to the next zero), the first one closes the block
// that was open, and the last one opens a new block.
struct WordCodes {
  uint32_t inner_codes;  // OR-ed into the word: code bytes at the zeros before the last
  uint8_t first_zero;    // byte offset of the first zero
  uint8_t last_zero;     // byte offset of the last zero
};

constexpr std::array<WordCodes, 16> MakeWordCodes() {
  std::array<WordCodes, 16> table{};
  for (uint32_t pattern = 1; pattern < 16; ++pattern) {
    WordCodes codes{0, 4, 0};
    int previous = -1;
    for (int k = 0; k < 4; ++k) {
      if ((pattern >> k & 1u) == 0) continue;
      if (previous < 0) codes.first_zero = static_cast<uint8_t>(k);
      if (previous >= 0) codes.inner_codes |= static_cast<uint32_t>(k - previous) << (8 * previous);
      previous = k;
    }
    codes.last_zero = static_cast<uint8_t>(previous);
    table[pattern] = codes;
  }
  return table;
}

constexpr std::array<WordCodes, 16> kWordCodes = MakeWordCodes();

}  // namespace

size_t EncodeFrameWordwise(uint8_t* packet, size_t packet_size, uint8_t* out) {
  const uint8_t* in = packet;
  const uint8_t* const words_end = packet + (packet_size & ~size_t{3});
  CobsCursor cobs{out, out + 1};
  uint32_t crc = ~0u;
  Crc32Bases tables;
  while (in != words_end) {
    uint32_t word;
    __builtin_memcpy(&word, in, sizeof(word));
    in += 4;
    crc = tables.Word(crc, word);
    uint8_t* const at = cobs.dst;
    cobs.dst = at + 4;
    const uint32_t zeros = ZeroBytes(word);
    if (zeros == 0) {
      __builtin_memcpy(at, &word, sizeof(word));
      // Only a zero-free word lengthens the block. Past 250 the next word could overfill it:
      // finish byte by byte, which splits full blocks.
      if (cobs.dst - cobs.code_at > 250) break;
      continue;
    }
    const WordCodes& codes = kWordCodes[ZeroPattern(zeros)];
    const uint32_t coded = word | codes.inner_codes;
    __builtin_memcpy(at, &coded, sizeof(coded));
    cobs.CloseAt(at + codes.first_zero);
    cobs.code_at = at + codes.last_zero;
  }
  // The rest of the packet (fewer than four bytes, or everything after a long zero-free run),
  // then the CRC, little-endian, in the spare bytes after the packet.
  const uint8_t* const packet_end = packet + packet_size;
  for (const uint8_t* p = in; p != packet_end; ++p) crc = Crc32Byte(crc, *p);
  crc = ~crc;
  __builtin_memcpy(packet + packet_size, &crc, kCrcSize);  // little-endian, as the frame wants
  cobs.Bytes(in, packet_end + kCrcSize);
  *cobs.dst = kFrameDelimiter;
  return static_cast<size_t>(cobs.dst - out) + 1;
}

}  // namespace palpa::protocol
