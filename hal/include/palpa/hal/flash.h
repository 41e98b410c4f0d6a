// NOR flash: sector erase sets bytes to 0xFF; programming can only clear bits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/status.h"

namespace palpa::hal {

using protocol::Status;

class Flash {
 public:
  /// Erases the sector holding `offset` (offset must be sector-aligned).
  Status Erase(uint32_t offset) { return DoErase(offset); }
  /// Programs bytes; each stored byte becomes (old & new), as NOR flash does.
  Status Program(uint32_t offset, const uint8_t* data, size_t size) {
    return DoProgram(offset, data, size);
  }
  Status Read(uint32_t offset, uint8_t* out, size_t size) { return DoRead(offset, out, size); }
  uint32_t sector_size() const { return DoSectorSize(); }
  uint32_t size() const { return DoSize(); }

 protected:
  ~Flash() = default;

 private:
  virtual Status DoErase(uint32_t offset) = 0;
  virtual Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) = 0;
  virtual Status DoRead(uint32_t offset, uint8_t* out, size_t size) = 0;
  virtual uint32_t DoSectorSize() const = 0;
  virtual uint32_t DoSize() const = 0;
};

}  // namespace palpa::hal
