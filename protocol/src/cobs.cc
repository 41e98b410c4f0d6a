// COBS encoder (Cheshire & Baker 1999), one pass, bounded by the caller's buffer.
#include "palpa/protocol/cobs.h"

#include "palpa/protocol/wire.h"

namespace palpa::protocol {
namespace {

// The common case, when the caller's buffer is large enough for the worst case: no bounds checks
// per byte (the telemetry frame is encoded every couple of ticks on a small MCU).
size_t CobsEncodeUnchecked(const uint8_t* in, size_t size, uint8_t* out) {
  const uint8_t* const end = in + size;
  uint8_t* code_at = out;
  uint8_t* dst = out + 1;
  // The block length is dst - code_at: no separate counter to keep in a byte-sized register.
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
      if (in == end) return static_cast<size_t>(dst - out);  // a full block ends the input
      code_at = dst++;
    }
  }
  *code_at = static_cast<uint8_t>(dst - code_at);
  return static_cast<size_t>(dst - out);
}

}  // namespace

size_t CobsEncode(const uint8_t* in, size_t size, uint8_t* out, size_t out_capacity) {
  if (out_capacity >= CobsMaxEncodedSize(size)) return CobsEncodeUnchecked(in, size, out);
  if (out_capacity == 0) return 0;
  size_t code_index = 0;
  size_t write = 1;
  uint8_t code = 1;
  for (size_t i = 0; i < size; ++i) {
    if (in[i] != 0) {
      if (write >= out_capacity) return 0;
      out[write++] = in[i];
      ++code;
    }
    if (in[i] == 0 || code == 0xFF) {
      out[code_index] = code;
      code = 1;
      // A full block that ends the input needs no further code byte.
      if (in[i] != 0 && i + 1 == size) return write;
      if (write >= out_capacity) return 0;
      code_index = write++;
    }
  }
  out[code_index] = code;
  return write;
}

}  // namespace palpa::protocol
