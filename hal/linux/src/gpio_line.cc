// Parses "CHIP:LINE" and finds the line through libgpiod v1, with errors naming what is missing.
#include "gpio_line.h"

#include <gpiod.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace palpa::hal::linux_gpio {

Opened<FoundLine> FindGpioLine(const std::string& spec) {
  const size_t colon = spec.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
    return {protocol::Status::kBadValue, "'" + spec + "': expected CHIP:LINE, e.g. gpiochip0:17"};
  const std::string chip_name = spec.substr(0, colon), line_text = spec.substr(colon + 1);
  char* end = nullptr;
  const unsigned long offset = std::strtoul(line_text.c_str(), &end, 10);
  if (end == line_text.c_str() || *end != '\0' || offset > 1023)
    return {protocol::Status::kBadValue,
            "'" + spec + "': line '" + line_text + "' is not a line number"};
  FoundLine found;
  found.chip = gpiod_chip_open_lookup(chip_name.c_str());
  if (found.chip == nullptr) {
    return {protocol::Status::kNotFound,
            "'" + spec + "': no GPIO chip '" + chip_name + "' (" + std::strerror(errno) + ")"};
  }
  found.line = gpiod_chip_get_line(found.chip, static_cast<unsigned>(offset));
  if (found.line == nullptr) {
    const std::string why = "'" + spec + "': chip " + chip_name + " has no line " + line_text +
                            " (" + std::strerror(errno) + ")";
    gpiod_chip_close(found.chip);
    return {protocol::Status::kNotFound, why};
  }
  return found;
}

}  // namespace palpa::hal::linux_gpio
