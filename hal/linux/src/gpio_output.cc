// libgpiod v1: open the chip by name, label, path or number; request one line as an output.
#include "palpa/hal/linux/gpio_output.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "gpio_line.h"

namespace palpa::hal::linux_gpio {

std::unique_ptr<GpioOutput> GpioOutput::Open(const std::string& spec, bool initial,
                                             std::string* error) {
  gpiod_chip* chip = nullptr;
  gpiod_line* line = FindGpioLine(spec, &chip, error);
  if (line == nullptr) return nullptr;
  if (gpiod_line_request_output(line, "palpa", initial ? 1 : 0) != 0) {
    *error = "'" + spec + "': cannot drive the line (" + std::strerror(errno) +
             "; is it used by another program?)";
    gpiod_chip_close(chip);
    return nullptr;
  }
  return std::unique_ptr<GpioOutput>(new GpioOutput(chip, line));
}

GpioOutput::~GpioOutput() {
  gpiod_line_release(line_);
  gpiod_chip_close(chip_);
}

Status GpioOutput::DoSet(bool level) {
  return gpiod_line_set_value(line_, level ? 1 : 0) == 0 ? Status::kOk : Status::kIoError;
}

}  // namespace palpa::hal::linux_gpio
