// Simulated NOR flash for the host: erase sets 0xFF, programming only clears bits, and a power
// cut can be scheduled to tear a program or an erase part-way.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "palpa/hal/flash.h"

namespace palpa::hal::fake {

class SimulatedNorFlash final : public Flash {
 public:
  SimulatedNorFlash(uint32_t size, uint32_t sector_size, uint32_t seed = 1);

  /// After `bytes` more bytes are programmed or erased, the power fails: the byte being written
  /// gets random bits (somewhere between old and new), nothing after it changes, and every later
  /// operation fails with kIoError until PowerOn().
  void CutPowerAfter(uint32_t bytes) { budget_ = static_cast<int64_t>(bytes); }
  void PowerOn() {
    budget_ = -1;
    powered_ = true;
  }
  bool powered() const { return powered_; }
  const std::vector<uint8_t>& contents() const { return memory_; }
  /// Replaces every byte, as a chip that kept them while it was off (palpa-sim --flash FILE);
  /// false when `size` is not the flash's size.
  bool Restore(const uint8_t* data, size_t size);
  uint32_t erases() const { return erases_; }
  /// Bytes erased or programmed so far: the scale CutPowerAfter counts in.
  uint64_t bytes_touched() const { return touched_; }

 private:
  Status DoErase(uint32_t offset) override;
  Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override;
  Status DoRead(uint32_t offset, uint8_t* out, size_t size) override;
  uint32_t DoSectorSize() const override { return sector_size_; }
  uint32_t DoSize() const override { return static_cast<uint32_t>(memory_.size()); }
  /// Consumes one byte of the power budget; false when the power has just failed.
  bool Spend();

  std::vector<uint8_t> memory_;
  uint32_t sector_size_;
  std::mt19937 rng_;
  int64_t budget_ = -1;  ///< -1: no power cut scheduled
  bool powered_ = true;
  uint32_t erases_ = 0;
  uint64_t touched_ = 0;
};

}  // namespace palpa::hal::fake
