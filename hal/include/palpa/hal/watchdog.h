// Independent watchdog: kicked only after a tick has written its outputs.
#pragma once

#include <cstdint>

namespace palpa::hal {

class Watchdog {
 public:
  void Start(uint32_t timeout_ms) { DoStart(timeout_ms); }
  void Kick() { DoKick(); }

 protected:
  ~Watchdog() = default;

 private:
  virtual void DoStart(uint32_t timeout_ms) = 0;
  virtual void DoKick() = 0;
};

}  // namespace palpa::hal
