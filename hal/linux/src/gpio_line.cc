// Parses "CHIP:LINE" and finds the line through libgpiod v1, with errors naming what is missing.
#include "gpio_line.h"

#include <gpiod.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace palpa::hal::linux_gpio {

gpiod_line* FindGpioLine(const std::string& spec, gpiod_chip** chip, std::string* error) {
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
  *chip = gpiod_chip_open_lookup(chip_name.c_str());
  if (*chip == nullptr) {
    *error = "'" + spec + "': no GPIO chip '" + chip_name + "' (" + std::strerror(errno) + ")";
    return nullptr;
  }
  gpiod_line* line = gpiod_chip_get_line(*chip, static_cast<unsigned>(offset));
  if (line == nullptr) {
    *error = "'" + spec + "': chip " + chip_name + " has no line " + line_text + " (" +
             std::strerror(errno) + ")";
    gpiod_chip_close(*chip);
    *chip = nullptr;
  }
  return line;
}

}  // namespace palpa::hal::linux_gpio
