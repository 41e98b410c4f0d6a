// Deterministic random numbers for the target check images, so a failing case repeats.
#pragma once

#include <cstdint>

namespace palpa::boards::mps2 {

class XorShift32 {
 public:
  explicit XorShift32(uint32_t seed) : state_(seed) {}
  uint32_t Next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return state_;
  }

 private:
  uint32_t state_;
};

}  // namespace palpa::boards::mps2
