// Table-driven CRC-32, slicing by 4 so the tick's telemetry framing stays cheap on a Cortex-M.
#include "palpa/protocol/crc32.h"

#include "crc32_tables.h"

namespace palpa::protocol {
namespace {

constexpr uint32_t kPolynomial = 0xEDB88320u;  // 0x04C11DB7 reflected

constexpr Crc32Tables MakeTables() {
  Crc32Tables tables{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int bit = 0; bit < 8; ++bit) c = (c & 1u) ? (c >> 1) ^ kPolynomial : c >> 1;
    tables[0][i] = c;
  }
  for (uint32_t i = 0; i < 256; ++i) {
    for (size_t t = 1; t < 4; ++t) {
      const uint32_t prev = tables[t - 1][i];
      tables[t][i] = (prev >> 8) ^ tables[0][prev & 0xFFu];
    }
  }
  return tables;
}

}  // namespace

constinit const Crc32Tables kCrc32Tables = MakeTables();

uint32_t Crc32Update(uint32_t crc, const uint8_t* data, size_t size) {
  uint32_t c = ~crc;
  const Crc32Bases tables;
  while (size >= 4) {
    uint32_t word;
    __builtin_memcpy(&word, data, sizeof(word));  // one load; both targets are little-endian
    c = tables.Word(c, word);
    data += 4;
    size -= 4;
  }
  while (size-- > 0) c = Crc32Byte(c, *data++);
  return ~c;
}

}  // namespace palpa::protocol
