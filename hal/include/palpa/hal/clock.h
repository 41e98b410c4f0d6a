// Monotonic microsecond clock, injected everywhere time matters.
#pragma once

#include <cstdint>

namespace palpa::hal {

class Clock {
 public:
  uint64_t NowMicros() { return DoNowMicros(); }

 protected:
  ~Clock() = default;

 private:
  virtual uint64_t DoNowMicros() = 0;
};

}  // namespace palpa::hal
