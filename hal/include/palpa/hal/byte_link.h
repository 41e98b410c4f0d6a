// Non-blocking byte link to the host (UART, USB CDC, pty, TCP).
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::hal {

class ByteLink {
 public:
  /// Copies up to `capacity` received bytes into `out`; returns how many (0 when none waiting).
  size_t Read(uint8_t* out, size_t capacity) { return DoRead(out, capacity); }
  /// Queues up to `size` bytes; returns how many were accepted (never blocks).
  size_t Write(const uint8_t* data, size_t size) { return DoWrite(data, size); }
  /// Bytes that Write would accept now.
  size_t WriteSpace() const { return DoWriteSpace(); }

 protected:
  ~ByteLink() = default;

 private:
  virtual size_t DoRead(uint8_t* out, size_t capacity) = 0;
  virtual size_t DoWrite(const uint8_t* data, size_t size) = 0;
  virtual size_t DoWriteSpace() const = 0;
};

}  // namespace palpa::hal
