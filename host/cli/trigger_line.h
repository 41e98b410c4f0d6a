// The study's trigger output on a GPIO line (palpa study run and palpa serve --trigger-gpio):
// taken low before the board starts, one 10 ms pulse per trigger event.
#pragma once

#include <memory>
#include <string>

#include "palpa/hal/linux/gpio_output.h"
#include "palpa/host/outcome.h"

namespace palpa::cli {

class TriggerLine {
 public:
  /// "CHIP:LINE", requested low now; an I/O error naming the option, the line and why.
  static host::Result<std::shared_ptr<TriggerLine>> Open(const std::string& spec);

  /// One trigger: high for 10 ms, long enough for a recorder sampling at 500 Hz or more to see it.
  /// Every event is one pulse; the event's record (a file, a notification) says which it was.
  void Pulse(const char* who);

 private:
  explicit TriggerLine(std::unique_ptr<hal::linux_gpio::GpioOutput> line)
      : line_(std::move(line)) {}
  std::unique_ptr<hal::linux_gpio::GpioOutput> line_;
  bool said_ = false;
};

}  // namespace palpa::cli
