// Consistent Overhead Byte Stuffing: removes every 0x00 so 0x00 can delimit frames.
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::protocol {

/// Encodes `size` bytes into `out` (no delimiter). Returns the encoded length, or 0 when
/// `out_capacity` is too small (nothing useful is left in `out` then).
size_t CobsEncode(const uint8_t* in, size_t size, uint8_t* out, size_t out_capacity);

/// Incremental decoder: feed the bytes between two delimiters one at a time.
class CobsDecoder {
 public:
  enum class Step : uint8_t { kByte, kNone };

  void Reset() {
    remaining_ = 0;
    pending_zero_ = false;
    started_ = false;
  }

  /// Feeds one non-zero encoded byte. Returns the number of decoded bytes written to out[0..1]
  /// (0, 1 or 2: a pending zero from the previous block plus this byte).
  size_t Feed(uint8_t byte, uint8_t out[2]) {
    if (remaining_ == 0) {  // code byte: starts a block
      size_t n = 0;
      if (pending_zero_) out[n++] = 0;
      pending_zero_ = false;
      remaining_ = static_cast<uint8_t>(byte - 1);
      block_short_ = byte != 0xFF;
      started_ = true;
      if (remaining_ == 0) pending_zero_ = block_short_;
      return n;
    }
    out[0] = byte;
    if (--remaining_ == 0) pending_zero_ = block_short_;
    return 1;
  }

  /// True when the bytes fed so far form a complete COBS encoding (called at the delimiter).
  bool Complete() const { return started_ && remaining_ == 0; }

 private:
  uint8_t remaining_ = 0;
  bool block_short_ = false;
  bool pending_zero_ = false;
  bool started_ = false;
};

}  // namespace palpa::protocol
