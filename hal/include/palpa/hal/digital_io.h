// Digital outputs (valves, pump enable) and inputs (E-stop), plus the pulsing-enable helper.
#pragma once

#include <cstdint>

#include "palpa/protocol/status.h"

namespace palpa::hal {

using protocol::Status;

/// One output. Writing it may fail (a GPIO line the kernel refuses), as a DAC's write may: the
/// caller decides what a failed write means for safety.
class DigitalOutput {
 public:
  /// kOk once the output holds `level`; an error when the write did not take effect.
  Status Set(bool level) { return DoSet(level); }

 protected:
  ~DigitalOutput() = default;

 private:
  virtual Status DoSet(bool level) = 0;
};

/// Outputs of one bit each, written together (a GPIO port's set/reset register): bit i drives
/// output i.
class DigitalPort {
 public:
  /// In Write's answer: every output took its bit.
  static constexpr uint8_t kAllWritten = 0xFF;

  /// Every output is attempted; returns the first output whose write failed, or kAllWritten.
  uint8_t Write(uint32_t bits) { return DoWrite(bits); }

 protected:
  ~DigitalPort() = default;

 private:
  virtual uint8_t DoWrite(uint32_t bits) = 0;
};

class DigitalInput {
 public:
  bool Read() { return DoRead(); }

 protected:
  ~DigitalInput() = default;

 private:
  virtual bool DoRead() = 0;
};

/// Drives an output that holds its load only while it keeps toggling (a charge pump or
/// retriggerable monostable in the valve driver): a hung loop stops toggling, and the dump and
/// supply shut-off valves fall back to their safe, unpowered positions in hardware.
class PulsingEnable {
 public:
  explicit PulsingEnable(DigitalOutput& output) : output_(output) {}

  /// Call once per tick. enable=true toggles the line; false holds it low. The output's answer.
  Status Tick(bool enable) {
    level_ = enable ? !level_ : false;
    return output_.Set(level_);
  }
  bool level() const { return level_; }

 private:
  DigitalOutput& output_;
  bool level_ = false;
};

}  // namespace palpa::hal
