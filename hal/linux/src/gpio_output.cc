// libgpiod v1: open the chip by name, label, path or number; request one line as an output.
#include "palpa/hal/linux/gpio_output.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "gpio_line.h"

namespace palpa::hal::linux_gpio {

Opened<std::unique_ptr<GpioOutput>> GpioOutput::Open(const std::string& spec, bool initial) {
  auto found = FindGpioLine(spec);
  if (!found.ok()) return {found.status, found.message};
  if (gpiod_line_request_output(found.value.line, "palpa", initial ? 1 : 0) != 0) {
    const std::string why = "'" + spec + "': cannot drive the line (" + std::strerror(errno) +
                            "; is it used by another program?)";
    gpiod_chip_close(found.value.chip);
    return {Status::kIoError, why};
  }
  return std::unique_ptr<GpioOutput>(new GpioOutput(found.value.chip, found.value.line));
}

GpioOutput::~GpioOutput() {
  gpiod_line_release(line_);
  gpiod_chip_close(chip_);
}

Status GpioOutput::DoSet(bool level) {
  return gpiod_line_set_value(line_, level ? 1 : 0) == 0 ? Status::kOk : Status::kIoError;
}

}  // namespace palpa::hal::linux_gpio
