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
  // Erase and program run from RAM (.ramfunc, copied there by startup with .data): a real
  // controller stalls instruction fetch from the bank it is erasing. Reached through the
  // interface's virtual calls (a register branch), so flash-to-RAM distance does not matter.
  Status DoErase(uint32_t offset) override;
  Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override;
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
