// Field visitors that turn a message's single Fields() definition into little-endian bytes and
// back.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "palpa/protocol/status.h"

namespace palpa::protocol {

/// Where decoding or encoding stopped: the field's name and its byte offset in the body.
struct FieldError {
  Status status = Status::kOk;
  const char* field = nullptr;
  uint16_t offset = 0;
};

template <typename T>
using Bound = std::type_identity_t<std::remove_cv_t<T>>;

template <typename T>
constexpr bool kIsWireScalar =
    std::is_same_v<T, uint8_t> || std::is_same_v<T, uint16_t> || std::is_same_v<T, uint32_t> ||
    std::is_same_v<T, uint64_t> || std::is_same_v<T, int32_t> || std::is_same_v<T, float>;

/// Enums on the wire are one byte (Status: two) and end with a kCount enumerator.
template <typename E>
constexpr uint64_t EnumCount() {
  return static_cast<uint64_t>(E::kCount);
}

/// Writes fields little-endian, checking each value against its range on the way out.
class BodyEncoder {
 public:
  BodyEncoder(uint8_t* out, size_t capacity) : out_(out), capacity_(capacity) {}

  template <typename T>
  void Field(const char* name, const T& value) {
    Field(name, value, std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max());
  }
  template <typename T>
  void Field(const char* name, const T& value, Bound<T> lo, Bound<T> hi) {
    static_assert(kIsWireScalar<T>, "not a wire scalar");
    if constexpr (std::is_same_v<T, float>) {
      if (!(value == value) || value - value != 0.0f) return Fail(Status::kBadValue, name);
    }
    if (!(value >= lo && value <= hi)) return Fail(Status::kOutOfRange, name);
    if constexpr (std::is_same_v<T, float>) {
      PutUnsigned<4>(std::bit_cast<uint32_t>(value), name);
    } else {
      const auto bits = static_cast<std::make_unsigned_t<T>>(value);
      PutUnsigned<sizeof(T)>(static_cast<uint64_t>(bits), name);
    }
  }
  void Flag(const char* name, const bool& value) { PutUnsigned<1>(value ? 1 : 0, name); }
  template <typename E>
  void Enum(const char* name, const E& value) {
    const auto raw = static_cast<uint64_t>(value);
    if (raw >= EnumCount<E>()) return Fail(Status::kBadValue, name);
    PutUnsigned<sizeof(E)>(raw, name);
  }
  template <typename T, size_t N>
  void Array(const char* name, const std::array<T, N>& items, const uint8_t& count) {
    static_assert(N <= 255);
    if (count > N) return Fail(Status::kOutOfRange, name);
    PutUnsigned<1>(count, name);
    for (size_t i = 0; i < count && ok(); ++i) {
      if constexpr (std::is_arithmetic_v<T>) {
        Field(name, items[i]);
      } else {
        T::Fields(*this, items[i]);
      }
    }
  }
  template <size_t N>
  void Bytes(const char* name, const std::array<uint8_t, N>& data, const uint8_t& size) {
    static_assert(N <= 255);
    if (size > N) return Fail(Status::kOutOfRange, name);
    PutUnsigned<1>(size, name);
    PutBytes(data.data(), size, name);
  }
  template <size_t N>
  void Fixed(const char* name, const std::array<uint8_t, N>& data) {
    PutBytes(data.data(), N, name);
  }
  /// Fixed-width printable ASCII, NUL-terminated and NUL-padded: at most N-1 characters, so a
  /// reader may always treat it as a C string.
  template <size_t N>
  void Text(const char* name, const std::array<char, N>& text) {
    if (!TextValid(text.data(), N)) return Fail(Status::kBadValue, name);
    PutBytes(reinterpret_cast<const uint8_t*>(text.data()), N, name);
  }

  bool ok() const { return error_.status == Status::kOk; }
  size_t size() const { return size_; }
  const FieldError& error() const { return error_; }

  /// Printable ASCII up to a NUL, NULs after it; a field with no NUL at all is refused.
  static bool TextValid(const char* text, size_t n) {
    bool ended = false;
    for (size_t i = 0; i < n; ++i) {
      const char c = text[i];
      if (c == '\0') {
        ended = true;
      } else if (ended || c < 0x20 || c > 0x7E) {
        return false;
      }
    }
    return ended;
  }

 private:
  void Fail(Status status, const char* name) {
    if (ok()) error_ = FieldError{status, name, static_cast<uint16_t>(size_)};
  }
  /// Little-endian, kBytes of them: the size is known at every call, so each byte is one store
  /// (a loop of 64-bit shifts was most of a telemetry frame's cost on a 32-bit core).
  template <size_t kBytes>
  void PutUnsigned(uint64_t value, const char* name) {
    static_assert(kBytes == 1 || kBytes == 2 || kBytes == 4 || kBytes == 8);
    if (!ok()) return;
    if (capacity_ - size_ < kBytes) return Fail(Status::kOverflow, name);
    uint8_t* out = out_ + size_;
    size_ += kBytes;
    const uint32_t low = static_cast<uint32_t>(value);
    out[0] = static_cast<uint8_t>(low);
    if constexpr (kBytes >= 2) out[1] = static_cast<uint8_t>(low >> 8);
    if constexpr (kBytes >= 4) {
      out[2] = static_cast<uint8_t>(low >> 16);
      out[3] = static_cast<uint8_t>(low >> 24);
    }
    if constexpr (kBytes == 8) {
      const uint32_t high = static_cast<uint32_t>(value >> 32);
      for (size_t i = 0; i < 4; ++i) out[4 + i] = static_cast<uint8_t>(high >> (8 * i));
    }
  }
  void PutBytes(const uint8_t* data, size_t n, const char* name) {
    if (!ok()) return;
    if (capacity_ - size_ < n) return Fail(Status::kOverflow, name);
    for (size_t i = 0; i < n; ++i) out_[size_++] = data[i];
  }

  uint8_t* out_;
  size_t capacity_;
  size_t size_ = 0;
  FieldError error_;
};

/// Reads fields little-endian, rejecting short bodies, out-of-range values, NaN/Inf and bad enums.
class BodyDecoder {
 public:
  BodyDecoder(const uint8_t* in, size_t size) : in_(in), size_(size) {}

  template <typename T>
  void Field(const char* name, T& value) {
    Field(name, value, std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max());
  }
  template <typename T>
  void Field(const char* name, T& value, Bound<T> lo, Bound<T> hi) {
    static_assert(kIsWireScalar<T>, "not a wire scalar");
    uint64_t raw = 0;
    const size_t start = pos_;
    if (!GetUnsigned<sizeof(T)>(raw, name)) return;
    T v;
    if constexpr (std::is_same_v<T, float>) {
      v = std::bit_cast<float>(static_cast<uint32_t>(raw));
      if (!(v == v) || v - v != 0.0f) return Fail(Status::kBadValue, name, start);
    } else {
      v = static_cast<T>(static_cast<std::make_unsigned_t<T>>(raw));
    }
    if (!(v >= lo && v <= hi)) return Fail(Status::kOutOfRange, name, start);
    value = v;
  }
  void Flag(const char* name, bool& value) {
    uint64_t raw = 0;
    const size_t start = pos_;
    if (!GetUnsigned<1>(raw, name)) return;
    if (raw > 1) return Fail(Status::kBadValue, name, start);
    value = raw == 1;
  }
  template <typename E>
  void Enum(const char* name, E& value) {
    uint64_t raw = 0;
    const size_t start = pos_;
    if (!GetUnsigned<sizeof(E)>(raw, name)) return;
    if (raw >= EnumCount<E>()) return Fail(Status::kBadValue, name, start);
    value = static_cast<E>(raw);
  }
  template <typename T, size_t N>
  void Array(const char* name, std::array<T, N>& items, uint8_t& count) {
    uint64_t raw = 0;
    const size_t start = pos_;
    if (!GetUnsigned<1>(raw, name)) return;
    if (raw > N) return Fail(Status::kOutOfRange, name, start);
    count = static_cast<uint8_t>(raw);
    for (size_t i = 0; i < count && ok(); ++i) {
      if constexpr (std::is_arithmetic_v<T>) {
        Field(name, items[i]);
      } else {
        T::Fields(*this, items[i]);
      }
    }
  }
  template <size_t N>
  void Bytes(const char* name, std::array<uint8_t, N>& data, uint8_t& size) {
    uint64_t raw = 0;
    const size_t start = pos_;
    if (!GetUnsigned<1>(raw, name)) return;
    if (raw > N) return Fail(Status::kOutOfRange, name, start);
    size = static_cast<uint8_t>(raw);
    GetBytes(data.data(), size, name);
  }
  template <size_t N>
  void Fixed(const char* name, std::array<uint8_t, N>& data) {
    GetBytes(data.data(), N, name);
  }
  template <size_t N>
  void Text(const char* name, std::array<char, N>& text) {
    const size_t start = pos_;
    if (!GetBytes(reinterpret_cast<uint8_t*>(text.data()), N, name)) return;
    if (!BodyEncoder::TextValid(text.data(), N)) Fail(Status::kBadValue, name, start);
  }

  /// Call after the last field: trailing bytes are an error too.
  void Finish() {
    if (ok() && pos_ != size_) Fail(Status::kBadLength, "(trailing bytes)", pos_);
  }
  /// Reports a cross-field rule broken after all fields were read.
  void Reject(Status status, const char* name) { Fail(status, name, 0); }

  bool ok() const { return error_.status == Status::kOk; }
  size_t position() const { return pos_; }
  const FieldError& error() const { return error_; }

 private:
  void Fail(Status status, const char* name, size_t at) {
    if (ok()) error_ = FieldError{status, name, static_cast<uint16_t>(at)};
  }
  /// Little-endian, kBytes of them, assembled in 32-bit halves (as BodyEncoder::PutUnsigned).
  template <size_t kBytes>
  bool GetUnsigned(uint64_t& value, const char* name) {
    static_assert(kBytes == 1 || kBytes == 2 || kBytes == 4 || kBytes == 8);
    if (!ok()) return false;
    if (size_ - pos_ < kBytes) {
      Fail(Status::kBadLength, name, pos_);
      return false;
    }
    const uint8_t* in = in_ + pos_;
    pos_ += kBytes;
    uint32_t low = in[0];
    if constexpr (kBytes >= 2) low |= static_cast<uint32_t>(in[1]) << 8;
    if constexpr (kBytes >= 4) {
      low |= static_cast<uint32_t>(in[2]) << 16 | static_cast<uint32_t>(in[3]) << 24;
    }
    value = low;
    if constexpr (kBytes == 8) {
      uint32_t high = 0;
      for (size_t i = 0; i < 4; ++i) high |= static_cast<uint32_t>(in[4 + i]) << (8 * i);
      value |= static_cast<uint64_t>(high) << 32;
    }
    return true;
  }
  bool GetBytes(uint8_t* out, size_t n, const char* name) {
    if (!ok()) return false;
    if (size_ - pos_ < n) {
      Fail(Status::kBadLength, name, pos_);
      return false;
    }
    for (size_t i = 0; i < n; ++i) out[i] = in_[pos_++];
    return true;
  }

  const uint8_t* in_;
  size_t size_;
  size_t pos_ = 0;
  FieldError error_;
};

}  // namespace palpa::protocol
