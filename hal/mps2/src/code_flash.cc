// NOR rules over the MPS2's code memory; erase and program placed in RAM.
#include "palpa/hal/mps2/code_flash.h"

namespace palpa::hal::mps2 {

__attribute__((section(".ramfunc"), noinline)) Status CodeFlash::DoErase(uint32_t offset) {
  if (offset % sector_size_ != 0 || offset >= size_) return Status::kOutOfRange;
  for (uint32_t i = 0; i < sector_size_; ++i) At(offset)[i] = 0xFF;
  return Status::kOk;
}

__attribute__((section(".ramfunc"), noinline)) Status CodeFlash::DoProgram(uint32_t offset,
                                                                           const uint8_t* data,
                                                                           size_t size) {
  if (offset > size_ || size > size_ - offset) return Status::kOutOfRange;
  for (size_t i = 0; i < size; ++i) At(offset)[i] &= data[i];
  return Status::kOk;
}

}  // namespace palpa::hal::mps2
