// Fused CRC-32 + COBS frame encoder: one load per four packet bytes, zero bytes found a word at a
// time, so telemetry framing stays within its instruction budget on a Cortex-M4.
#include "frame_encoder.h"

#include <array>

#include "crc32_tables.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {
namespace {

// Bit 7 of each zero byte of `word`, exactly (no borrow between bytes).
inline uint32_t ZeroBytes(uint32_t word) {
  return ~(((word & 0x7F7F7F7Fu) + 0x7F7F7F7Fu) | word) & 0x80808080u;
}

// Which of the four bytes are not zero, as bits 0..3 (bit k: the k-th byte in memory). One
// multiply gathers bits 7, 15, 23, 31 into 28..31 without carries.
inline uint32_t NonZeroPattern(uint32_t zero_bytes) {
  return ((zero_bytes * 0x00204081u) >> 28) ^ 0xFu;
}

// What a word with zero bytes in a given pattern does to the COBS output, found once per pattern
// instead of zero by zero: every zero but the last becomes the code byte of a block that ends
// inside the word (its length is the distance to the next zero), the first one closes the block
// that was open, and the last one opens a new block.
// Indexed by the non-zero pattern (the ARMv7E-M loop gets that one from its byte-wise add).
struct alignas(8) WordCodes {
  uint32_t inner_codes;  // OR-ed into the word: code bytes at the zeros before the last
  int8_t first_zero;     // offset of the first zero from the end of the word (-4 … -1)
  int8_t last_zero;      // offset of the last zero from the end of the word
};
static_assert(sizeof(WordCodes) == 8, "the ARMv7E-M loop loads an entry with one LDRD");

constexpr std::array<WordCodes, 16> MakeWordCodes() {
  std::array<WordCodes, 16> table{};
  for (uint32_t non_zero = 0; non_zero < 15; ++non_zero) {
    WordCodes codes{0, 4, 0};
    int previous = -1;
    for (int k = 0; k < 4; ++k) {
      if ((non_zero >> k & 1u) != 0) continue;
      if (previous < 0) codes.first_zero = static_cast<int8_t>(k - 4);
      if (previous >= 0) codes.inner_codes |= static_cast<uint32_t>(k - previous) << (8 * previous);
      previous = k;
    }
    codes.last_zero = static_cast<int8_t>(previous - 4);
    table[non_zero] = codes;
  }
  return table;
}

constexpr std::array<WordCodes, 16> kWordCodes = MakeWordCodes();

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

  // Copies one word; its zero bytes become code bytes. False when it had no zero, which is the
  // only case that lengthens the open block.
  bool Word(uint32_t word) {
    uint8_t* const at = dst;
    dst = at + 4;
    const uint32_t zeros = ZeroBytes(word);
    if (zeros == 0) {
      __builtin_memcpy(at, &word, sizeof(word));
      return false;
    }
    const WordCodes& codes = kWordCodes[NonZeroPattern(zeros)];
    const uint32_t coded = word | codes.inner_codes;
    __builtin_memcpy(at, &coded, sizeof(coded));
    CloseAt(dst + codes.first_zero);
    code_at = dst + codes.last_zero;
    return true;
  }

  // One byte, when the open block cannot reach 254 data bytes before the input ends.
  void ShortByte(uint8_t byte) {
    if (byte == 0) {
      CloseAt(dst++);
    } else {
      *dst++ = byte;
    }
  }

  // Byte-at-a-time COBS for long zero-free runs (254-byte blocks).
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

// Where the word loop stopped; the layout is shared with the ARMv7E-M loop.
struct FrameWords {
  const uint8_t* in;
  uint8_t* dst;
  uint8_t* code_at;
  uint32_t crc;  // inverted CRC register
};

#if defined(PALPA_FRAME_WORDS_V7EM)
extern "C" void palpa_frame_words_v7em(FrameWords* state, const uint8_t* words_end,
                                       const uint32_t* crc_tables, const WordCodes* codes);

void WordLoop(FrameWords& s, const uint8_t* words_end) {
  palpa_frame_words_v7em(&s, words_end, kCrc32Tables[0].data(), kWordCodes.data());
}
#else
void WordLoop(FrameWords& s, const uint8_t* words_end) {
  CobsCursor cobs{s.code_at, s.dst};
  const uint8_t* in = s.in;
  uint32_t crc = s.crc;
  Crc32Bases tables;
  while (in != words_end) {
    uint32_t word;
    __builtin_memcpy(&word, in, sizeof(word));
    in += 4;
    crc = tables.Word(crc, word);
    // Past 250 the next word could overfill the block: finish byte by byte, which splits it.
    if (!cobs.Word(word) && cobs.dst - cobs.code_at > 250) break;
  }
  s = FrameWords{in, cobs.dst, cobs.code_at, crc};
}
#endif

}  // namespace

size_t EncodeFrameWordwise(uint8_t* packet, size_t packet_size, uint8_t* out) {
  FrameWords words{packet, out + 1, out, ~0u};
  WordLoop(words, packet + (packet_size & ~size_t{3}));
  const uint8_t* const in = words.in;
  uint32_t crc = words.crc;
  CobsCursor cobs{words.code_at, words.dst};
  // The rest of the packet (fewer than four bytes, or everything after a long zero-free run),
  // then the CRC, little-endian, in the spare bytes after the packet.
  const uint8_t* const packet_end = packet + packet_size;
  for (const uint8_t* p = in; p != packet_end; ++p) crc = Crc32Byte(crc, *p);
  crc = ~crc;
  __builtin_memcpy(packet + packet_size, &crc, kCrcSize);
  const uint8_t* const frame_end = packet_end + kCrcSize;
  constexpr ptrdiff_t kShortTail = kCrcSize + 3;
  if (frame_end - in <= kShortTail && cobs.dst - cobs.code_at + kShortTail < 0xFF) {
    // The usual end: four to seven bytes that cannot fill a block, one word and the rest.
    uint32_t word;
    __builtin_memcpy(&word, in, sizeof(word));
    cobs.Word(word);
    for (const uint8_t* p = in + 4; p != frame_end; ++p) cobs.ShortByte(*p);
    *cobs.code_at = static_cast<uint8_t>(cobs.dst - cobs.code_at);
  } else {
    cobs.Bytes(in, frame_end);
  }
  *cobs.dst = kFrameDelimiter;
  return static_cast<size_t>(cobs.dst - out) + 1;
}

}  // namespace palpa::protocol
