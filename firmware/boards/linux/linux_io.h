// palpa-linux-board's hardware behind the HAL: the monotonic clock, the Modbus analogue I/O module,
// the valves and enables on GPIO output lines and the E-stop on a GPIO input with edge events.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "board_file.h"
#include "palpa/core/board.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/linux/gpio_edge_input.h"
#include "palpa/hal/linux/gpio_output.h"
#include "palpa/hal/linux/modbus_aio.h"
#include "palpa/hal/linux/opened.h"

namespace palpa::linux_board {

/// CLOCK_MONOTONIC in microseconds: the clock the tick loop sleeps on.
class MonotonicClock final : public hal::Clock {
 private:
  uint64_t DoNowMicros() override;
};

/// A GPIO output, or nothing when the configuration names no line for it.
class OptionalOutput final : public hal::DigitalOutput {
 public:
  std::unique_ptr<hal::linux_gpio::GpioOutput> line;

 private:
  hal::Status DoSet(bool level) override { return line ? line->Set(level) : hal::Status::kOk; }
};

/// The lines' dump valve drivers: bit i set releases line i's valve (unpowered: open), so the
/// GPIO line is low; clear powers it shut. Every valve is written; the first that failed is
/// reported.
class ValvePort final : public hal::DigitalPort {
 public:
  std::vector<std::unique_ptr<hal::linux_gpio::GpioOutput>> valves;

 private:
  uint8_t DoWrite(uint32_t bits) override {
    uint8_t failed = kAllWritten;
    for (size_t i = 0; i < valves.size(); ++i) {
      if (valves[i]->Set((bits >> i & 1u) == 0) != hal::Status::kOk && failed == kAllWritten)
        failed = static_cast<uint8_t>(i);
    }
    return failed;
  }
};

/// The E-stop line as the tick reads it (GpioEdgeInput's latch), saying on stderr, once, why the
/// line could not be read: the fault the core latches (estop_pin) names no reason, and a line that
/// failed once stays asserted, so every later tick would repeat the same words.
class EstopInput final : public hal::DigitalInput {
 public:
  std::unique_ptr<hal::linux_gpio::GpioEdgeInput> line;

 private:
  bool DoRead() override;
  bool said_ = false;
};

class LinuxIo {
 public:
  /// Opens the module (its watchdog armed, 0 V written) and every GPIO line at its safe level
  /// (low: enables off, valves released); refused with the line's or module's status, the
  /// message naming the field.
  static hal::Opened<std::unique_ptr<LinuxIo>> Open(const BoardFile& file);

  /// The board's hardware; `link` carries the host's bytes.
  core::BoardIo Io(hal::ByteLink& link);
  /// Everything to its safe value: 0 V on every module output, every GPIO line low. kIoError
  /// when the module could not be written (its own watchdog then zeroes the outputs) or a GPIO
  /// line refused its level, the message saying which.
  hal::Done WriteSafe();

  hal::linux_aio::ModbusAioModule& module() { return *module_; }
  size_t gpio_lines() const;

 private:
  LinuxIo() = default;
  MonotonicClock clock_;
  std::unique_ptr<hal::linux_aio::ModbusAioModule> module_;
  OptionalOutput supply_, dump_, pump_;
  ValvePort valves_;
  EstopInput estop_;
};

}  // namespace palpa::linux_board
