// NOR flash model with torn programs and erases.
#include "palpa/hal/fake/simulated_nor_flash.h"

#include <cstring>

namespace palpa::hal::fake {

SimulatedNorFlash::SimulatedNorFlash(uint32_t size, uint32_t sector_size, uint32_t seed)
    : memory_(size, 0xFF), sector_size_(sector_size), rng_(seed) {}

bool SimulatedNorFlash::Spend() {
  if (!powered_) return false;
  ++touched_;
  if (budget_ < 0) return true;
  if (budget_ == 0) {
    powered_ = false;
    return false;
  }
  --budget_;
  return true;
}

Status SimulatedNorFlash::DoErase(uint32_t offset) {
  if (offset % sector_size_ != 0 || offset >= memory_.size()) return Status::kOutOfRange;
  ++erases_;
  for (uint32_t i = 0; i < sector_size_; ++i) {
    if (!Spend()) {
      // A torn erase leaves the rest of the sector with random bits set.
      for (uint32_t j = i; j < sector_size_; ++j)
        memory_[offset + j] |= static_cast<uint8_t>(rng_());
      return Status::kIoError;
    }
    memory_[offset + i] = 0xFF;
  }
  return Status::kOk;
}

Status SimulatedNorFlash::DoProgram(uint32_t offset, const uint8_t* data, size_t size) {
  if (offset > memory_.size() || size > memory_.size() - offset) return Status::kOutOfRange;
  for (size_t i = 0; i < size; ++i) {
    if (!Spend()) {
      // Some of the bits being cleared made it, some did not.
      const uint8_t partial = static_cast<uint8_t>(data[i] | static_cast<uint8_t>(rng_()));
      memory_[offset + i] &= partial;
      return Status::kIoError;
    }
    memory_[offset + i] &= data[i];
  }
  return Status::kOk;
}

bool SimulatedNorFlash::Restore(const uint8_t* data, size_t size) {
  if (size != memory_.size()) return false;
  std::memcpy(memory_.data(), data, size);
  return true;
}

Status SimulatedNorFlash::DoRead(uint32_t offset, uint8_t* out, size_t size) {
  if (!powered_) return Status::kIoError;
  if (offset > memory_.size() || size > memory_.size() - offset) return Status::kOutOfRange;
  std::memcpy(out, memory_.data() + offset, size);
  return Status::kOk;
}

}  // namespace palpa::hal::fake
