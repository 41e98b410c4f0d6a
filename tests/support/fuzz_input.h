// A fuzzer's input read as a stream of small values; past its end every byte reads as 0, so a
// short input is still a complete one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace palpa::testing {

class FuzzInput {
 public:
  FuzzInput(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool done() const { return at_ >= size_; }
  uint8_t Byte() { return at_ < size_ ? data_[at_++] : 0; }
  /// Little-endian, like the wire (the low part read first: the operands of | are unsequenced).
  uint16_t Word() {
    const uint8_t low = Byte();
    return static_cast<uint16_t>(low | Byte() << 8);
  }
  uint32_t Word32() {
    const uint16_t low = Word();
    return low | static_cast<uint32_t>(Word()) << 16;
  }
  uint64_t Word64() {
    const uint32_t low = Word32();
    return low | static_cast<uint64_t>(Word32()) << 32;
  }
  /// Any bit pattern: NaN, infinities and denormals included.
  float FloatBits() {
    const uint32_t bits = Word32();
    float v;
    std::memcpy(&v, &bits, sizeof(v));
    return v;
  }
  /// Everything not read yet.
  std::string Rest() {
    std::string s(reinterpret_cast<const char*>(data_ + at_), size_ - at_);
    at_ = size_;
    return s;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

}  // namespace palpa::testing
