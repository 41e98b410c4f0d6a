// Waiting in a test for something another process or thread does: shared by the suites that
// start programs (the Modbus module's, the Linux board's, the real-kernel guest's).
#pragma once

#include <chrono>
#include <functional>
#include <thread>

namespace palpa::testing {

/// Polls `done` every 10 ms for up to `seconds`; whether it came true.
inline bool WaitUntil(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

}  // namespace palpa::testing
