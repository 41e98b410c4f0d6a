// The MPS2's code memory as NOR flash. QEMU models the 4 MB at 0x0 as RAM, so erase and program
// are emulated with NOR's rules (erase sets 0xFF, programming only clears bits); a real board's
// flash controller sits behind the same interface (hal/stm32f4).
#pragma once

#include <cstdint>

#include "palpa/hal/flash.h"

namespace palpa::hal::mps2 {

class CodeFlash final : public Flash {
 public:
  CodeFlash(uint32_t base, uint32_t size, uint32_t sector_size)
      : base_(base), size_(size), sector_size_(sector_size) {}

 private:
  uint8_t* At(uint32_t offset) const { return reinterpret_cast<uint8_t*>(base_ + offset); }
  Status DoErase(uint32_t offset) override {
    if (offset % sector_size_ != 0 || offset >= size_) return Status::kOutOfRange;
    for (uint32_t i = 0; i < sector_size_; ++i) At(offset)[i] = 0xFF;
    return Status::kOk;
  }
  Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override {
    if (offset > size_ || size > size_ - offset) return Status::kOutOfRange;
    for (size_t i = 0; i < size; ++i) At(offset)[i] &= data[i];
    return Status::kOk;
  }
  Status DoRead(uint32_t offset, uint8_t* out, size_t size) override {
    if (offset > size_ || size > size_ - offset) return Status::kOutOfRange;
    for (size_t i = 0; i < size; ++i) out[i] = At(offset)[i];
    return Status::kOk;
  }
  uint32_t DoSectorSize() const override { return sector_size_; }
  uint32_t DoSize() const override { return size_; }

  uint32_t base_, size_, sector_size_;
};

}  // namespace palpa::hal::mps2
