// libgpiod v1: open the chip by name, label, path or number; request one line as an output.
#include "palpa/hal/linux/gpio_output.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

namespace palpa::hal::linux_gpio {

gpiod_line* OpenLine(const std::string& spec, gpiod_chip** chip_out, std::string* error) {
  const size_t colon = spec.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size()) {
    *error = "'" + spec + "': expected CHIP:LINE, e.g. gpiochip0:17";
    return nullptr;
  }
  const std::string chip_name = spec.substr(0, colon), line_text = spec.substr(colon + 1);
  char* end = nullptr;
  const unsigned long offset = std::strtoul(line_text.c_str(), &end, 10);
  if (end == line_text.c_str() || *end != '\0' || offset > 1023) {
    *error = "'" + spec + "': line '" + line_text + "' is not a line number";
    return nullptr;
  }
  gpiod_chip* chip = gpiod_chip_open_lookup(chip_name.c_str());
  if (chip == nullptr) {
    *error = "'" + spec + "': no GPIO chip '" + chip_name + "' (" + std::strerror(errno) + ")";
    return nullptr;
  }
  gpiod_line* line = gpiod_chip_get_line(chip, static_cast<unsigned>(offset));
  if (line == nullptr) {
    *error = "'" + spec + "': chip " + chip_name + " has no line " + line_text + " (" +
             std::strerror(errno) + ")";
    gpiod_chip_close(chip);
    return nullptr;
  }
  *chip_out = chip;
  return line;
}

std::unique_ptr<GpioOutput> GpioOutput::Open(const std::string& spec, bool initial,
                                             std::string* error) {
  gpiod_chip* chip = nullptr;
  gpiod_line* line = OpenLine(spec, &chip, error);
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

void GpioOutput::DoSet(bool level) {
  if (gpiod_line_set_value(line_, level ? 1 : 0) != 0) ok_ = false;
}

}  // namespace palpa::hal::linux_gpio
