// Digital outputs (valves, pump enable) and inputs (E-stop), plus the pulsing-enable helper.
#pragma once

#include <cstdint>

namespace palpa::hal {

class DigitalOutput {
 public:
  void Set(bool level) { DoSet(level); }

 protected:
  ~DigitalOutput() = default;

 private:
  virtual void DoSet(bool level) = 0;
};

/// Outputs of one bit each, written together (a GPIO port's set/reset register): bit i drives
/// output i.
class DigitalPort {
 public:
  void Write(uint32_t bits) { DoWrite(bits); }

 protected:
  ~DigitalPort() = default;

 private:
  virtual void DoWrite(uint32_t bits) = 0;
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

  /// Call once per tick. enable=true toggles the line; false holds it low.
  void Tick(bool enable) {
    level_ = enable ? !level_ : false;
    output_.Set(level_);
  }
  bool level() const { return level_; }

 private:
  DigitalOutput& output_;
  bool level_ = false;
};

}  // namespace palpa::hal
