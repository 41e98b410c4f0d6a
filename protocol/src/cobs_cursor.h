// COBS encoding state shared by the plain encoder and the frame encoder's byte-wise paths.
#pragma once

#include <cstdint>

namespace palpa::protocol {

/// `code_at` is the pending code byte of the open block, `dst` the next free byte; the block
/// length (code byte included) is dst - code_at, so no counter has to live in a byte register.
struct CobsCursor {
  uint8_t* code_at;
  uint8_t* dst;

  /// Ends the open block at `zero_at`, where a zero byte was (or is about to be) written: that
  /// byte becomes the next block's code byte.
  void CloseAt(uint8_t* zero_at) {
    *code_at = static_cast<uint8_t>(zero_at - code_at);
    code_at = zero_at;
  }

  /// One byte, when the open block cannot reach 254 data bytes before the input ends.
  void ShortByte(uint8_t byte) {
    if (byte == 0) {
      CloseAt(dst++);
    } else {
      *dst++ = byte;
    }
  }

  /// Encodes [in, end) byte by byte, splitting 254-byte blocks, and closes the last block.
  void Bytes(const uint8_t* in, const uint8_t* end) {
    while (in != end) {
      const uint8_t byte = *in++;
      if (byte == 0) {
        CloseAt(dst++);
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

}  // namespace palpa::protocol
