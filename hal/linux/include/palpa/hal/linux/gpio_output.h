// A GPIO output line on Linux through libgpiod (v1 API): the reset and boot pins of a board the
// host flashes, and the Linux board's valves and enables. Tests link a fake libgpiod in its place
// (a link-time seam).
#pragma once

#include <memory>
#include <string>

#include "palpa/hal/digital_io.h"
#include "palpa/hal/linux/opened.h"

struct gpiod_chip;
struct gpiod_line;

namespace palpa::hal::linux_gpio {

class GpioOutput final : public DigitalOutput {
 public:
  /// "CHIP:LINE" (gpiochip0:17, or a chip's label or number: 0:17). Requests the line as an
  /// output at `initial`. A failure names the chip, the line and the reason: kBadValue (not
  /// CHIP:LINE), kNotFound (no such chip or line), kIoError (the kernel refused the request: a
  /// line another program holds).
  static Opened<std::unique_ptr<GpioOutput>> Open(const std::string& spec, bool initial);
  ~GpioOutput();
  GpioOutput(const GpioOutput&) = delete;
  GpioOutput& operator=(const GpioOutput&) = delete;

 private:
  GpioOutput(gpiod_chip* chip, gpiod_line* line) : chip_(chip), line_(line) {}
  /// kIoError when the kernel refused the value (the line keeps its level).
  Status DoSet(bool level) override;
  gpiod_chip* chip_;
  gpiod_line* line_;
};

}  // namespace palpa::hal::linux_gpio
