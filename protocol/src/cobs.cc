// COBS encoder (Cheshire & Baker 1999), one pass, bounded by the caller's buffer.
#include "palpa/protocol/cobs.h"

#include "cobs_cursor.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {
namespace {

// The common case, when the caller's buffer is large enough for the worst case: no bounds checks
// per byte (the telemetry frame is encoded every couple of ticks on a small MCU).
size_t CobsEncodeUnchecked(const uint8_t* in, size_t size, uint8_t* out) {
  CobsCursor cobs{out, out + 1};
  cobs.Bytes(in, in + size);
  return static_cast<size_t>(cobs.dst - out);
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
