// What SHA-256 and SHA-512 share around their compression functions (FIPS 180-4 §5.1, §5.2): the
// message cut into blocks, and the padding that ends in the message's length in bits.
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::protocol {

/// Buffers a message for a compression function over `kBlockBytes`-byte blocks whose padding
/// ends in a `kLengthBytes`-byte big-endian bit count. `compress(const uint8_t* block)` is the
/// hasher's own; whole blocks go to it straight from the input, not through the buffer.
template <size_t kBlockBytes, size_t kLengthBytes>
class Sha2Blocks {
  static_assert(kLengthBytes >= 8 && kLengthBytes < kBlockBytes);

 public:
  void Reset() {
    length_ = 0;
    buffered_ = 0;
  }

  template <class Compress>
  void Update(const uint8_t* data, size_t size, Compress compress) {
    length_ += size;
    while (size > 0) {
      if (buffered_ == 0 && size >= kBlockBytes) {
        compress(data);
        data += kBlockBytes;
        size -= kBlockBytes;
        continue;
      }
      const size_t take = size < kBlockBytes - buffered_ ? size : kBlockBytes - buffered_;
      for (size_t i = 0; i < take; ++i) buffer_[buffered_ + i] = data[i];
      buffered_ += take;
      data += take;
      size -= take;
      if (buffered_ == kBlockBytes) {
        compress(buffer_);
        buffered_ = 0;
      }
    }
  }

  /// The padding after the message (the 1 bit, zeros, the length; messages under 2^61 bytes, so
  /// a 16-byte length's high half is 0), fed to `update(const uint8_t* data, size_t size)`: the
  /// hasher's own Update, which compresses the last block or two. Reset() before reuse.
  template <class Feed>
  void Pad(Feed update) {
    const uint64_t bits = length_ * 8;
    const uint8_t one = 0x80, zero = 0;
    update(&one, 1);
    while (buffered_ != kBlockBytes - kLengthBytes) update(&zero, 1);
    uint8_t tail[kLengthBytes];
    for (size_t i = 0; i < kLengthBytes - 8; ++i) tail[i] = 0;
    for (size_t i = 0; i < 8; ++i)
      tail[kLengthBytes - 8 + i] = static_cast<uint8_t>(bits >> (56 - 8 * i));
    update(tail, kLengthBytes);
  }

 private:
  uint8_t buffer_[kBlockBytes];
  uint64_t length_ = 0;  ///< bytes hashed
  size_t buffered_ = 0;
};

}  // namespace palpa::protocol
