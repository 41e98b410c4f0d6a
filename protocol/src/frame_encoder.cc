// Frame encoder: COBS(packet ‖ crc32_le(packet)) ‖ 0x00 in one pass a word at a time — CRC and
// COBS share each load and a word's zero bytes are coded by pattern — so telemetry framing stays
// within its instruction budget on a Cortex-M4.
#include <array>

#include "cobs_cursor.h"
#include "crc32_tables.h"
#include "palpa/protocol/cobs.h"
#include "palpa/protocol/crc32.h"
#include "palpa/protocol/framing.h"

namespace palpa::protocol {
namespace {

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
struct alignas(8) WordCodes {
  uint32_t inner_codes;  // OR-ed into the word: code bytes at the zeros before the last
  int8_t first_zero;     // offset of the first zero from the end of the word (-4 … -1)
  int8_t last_zero;      // offset of the last zero from the end of the word
};
static_assert(sizeof(WordCodes) == 8, "the ARMv7E-M loop loads an entry with one LDRD");

constexpr std::array<WordCodes, 16> MakeWordCodes() {
  std::array<WordCodes, 16> table{};
  for (uint32_t pattern = 1; pattern < 16; ++pattern) {
    WordCodes codes{0, 0, 0};
    int previous = -1;
    for (int k = 0; k < 4; ++k) {
      if ((pattern >> k & 1u) == 0) continue;
      if (previous < 0) codes.first_zero = static_cast<int8_t>(k - 4);
      if (previous >= 0) codes.inner_codes |= static_cast<uint32_t>(k - previous) << (8 * previous);
      previous = k;
    }
    codes.last_zero = static_cast<int8_t>(previous - 4);
    table[pattern] = codes;
  }
  return table;
}

constexpr std::array<WordCodes, 16> kWordCodes = MakeWordCodes();

// Copies one word; its zero bytes become code bytes. False when it had no zero, which is the
// only case that lengthens the open block.
inline bool CobsWord(CobsCursor& cobs, uint32_t word) {
  uint8_t* const at = cobs.dst;
  cobs.dst = at + 4;
  const uint32_t zeros = ZeroBytes(word);
  if (zeros == 0) {
    __builtin_memcpy(at, &word, sizeof(word));
    return false;
  }
  const WordCodes& codes = kWordCodes[ZeroPattern(zeros)];
  const uint32_t coded = word | codes.inner_codes;
  __builtin_memcpy(at, &coded, sizeof(coded));
  cobs.CloseAt(cobs.dst + codes.first_zero);
  cobs.code_at = cobs.dst + codes.last_zero;
  return true;
}

// Where the word loop stopped; the layout is shared with the ARMv7E-M loop.
struct FrameWords {
  const uint8_t* in;
  uint8_t* dst;
  uint8_t* code_at;
  uint32_t crc;  // inverted CRC register
};

// Continues the inverted CRC register over [rest, packet_end) and writes the CRC, little-endian,
// in the spare bytes after the packet.
void AppendCrc(uint32_t crc_register, const uint8_t* rest, uint8_t* packet_end) {
  const uint32_t crc = Crc32Update(~crc_register, rest, static_cast<size_t>(packet_end - rest));
  __builtin_memcpy(packet_end, &crc, kCrcSize);
}

// The open block may grow by up to seven bytes in the tail (three packet bytes and the CRC).
constexpr ptrdiff_t kLongestTail = 3 + kCrcSize;

#if defined(PALPA_FRAME_WORDS_V7EM)
extern "C" uint8_t* palpa_frame_v7em(FrameWords* state, uint8_t* packet_end,
                                     const uint32_t* crc_tables, const WordCodes* codes);

uint8_t* FastFrame(FrameWords& s, uint8_t* packet_end) {
  return palpa_frame_v7em(&s, packet_end, kCrc32Tables[0].data(), kWordCodes.data());
}
#else
// Encodes the whole frame unless a block could fill up: returns the end of the frame (after the
// delimiter), or nullptr with `s` saying where the byte-wise path has to take over.
uint8_t* FastFrame(FrameWords& s, uint8_t* packet_end) {
  CobsCursor cobs{s.code_at, s.dst};
  const uint8_t* in = s.in;
  const uint8_t* const words_end = in + ((packet_end - in) & ~ptrdiff_t{3});
  uint32_t crc = s.crc;
  Crc32Bases tables;
  while (in != words_end) {
    uint32_t word;
    __builtin_memcpy(&word, in, sizeof(word));
    in += 4;
    crc = tables.Word(crc, word);
    // Past 250 the next word could overfill the block: finish byte by byte, which splits it.
    if (!CobsWord(cobs, word) && cobs.dst - cobs.code_at > 250) break;
  }
  s = FrameWords{in, cobs.dst, cobs.code_at, crc};
  if (in != words_end || cobs.dst - cobs.code_at + kLongestTail >= 0xFF) return nullptr;
  // The last one to three packet bytes into the CRC, the CRC after the packet, then four to
  // seven bytes that cannot fill a block: one word and the rest.
  AppendCrc(crc, in, packet_end);
  uint32_t word;
  __builtin_memcpy(&word, in, sizeof(word));
  CobsWord(cobs, word);
  for (const uint8_t* p = in + 4; p != packet_end + kCrcSize; ++p) cobs.ShortByte(*p);
  *cobs.code_at = static_cast<uint8_t>(cobs.dst - cobs.code_at);
  *cobs.dst = kFrameDelimiter;
  return cobs.dst + 1;
}
#endif

// Writes COBS(packet ‖ crc32_le(packet)) ‖ 0x00 and returns its length. `packet` has kCrcSize
// spare bytes after it (the CRC goes there); `out` holds CobsMaxEncodedSize(size + 4) + 1 bytes.
size_t EncodeFrameWordwise(uint8_t* packet, size_t packet_size, uint8_t* out) {
  uint8_t* const packet_end = packet + packet_size;
  FrameWords words{packet, out + 1, out, ~0u};
  if (const uint8_t* end = FastFrame(words, packet_end)) return static_cast<size_t>(end - out);
  // A long zero-free run: the rest of the packet and the CRC byte by byte, splitting full blocks.
  AppendCrc(words.crc, words.in, packet_end);
  CobsCursor cobs{words.code_at, words.dst};
  cobs.Bytes(words.in, packet_end + kCrcSize);
  *cobs.dst = kFrameDelimiter;
  return static_cast<size_t>(cobs.dst - out) + 1;
}

}  // namespace

Result<size_t> EncodeFrameInPlace(uint8_t* packet, size_t packet_size, uint8_t* out,
                                  size_t out_capacity) {
  if (packet_size < kHeaderSize || packet_size > kMaxPacketSize) return Status::kBadLength;
  // Room for the largest frame (the telemetry buffers have it) avoids a division per frame.
  if (out_capacity >= kMaxFrameSize || out_capacity > CobsMaxEncodedSize(packet_size + kCrcSize)) {
    return EncodeFrameWordwise(packet, packet_size, out);
  }
  AppendCrc(~0u, packet, packet + packet_size);
  if (out_capacity < 1) return Status::kOverflow;
  const size_t encoded = CobsEncode(packet, packet_size + kCrcSize, out, out_capacity - 1);
  if (encoded == 0) return Status::kOverflow;
  out[encoded] = kFrameDelimiter;
  return encoded + 1;
}

Result<size_t> EncodeFrame(const uint8_t* packet, size_t packet_size, uint8_t* out,
                           size_t out_capacity) {
  if (packet_size < kHeaderSize || packet_size > kMaxPacketSize) return Status::kBadLength;
  uint8_t raw[kMaxPacketSize + kCrcSize];
  for (size_t i = 0; i < packet_size; ++i) raw[i] = packet[i];
  return EncodeFrameInPlace(raw, packet_size, out, out_capacity);
}

}  // namespace palpa::protocol
