// Finds the line a "CHIP:LINE" spec names (libgpiod v1), shared by the output and input classes.
#pragma once

#include <string>

struct gpiod_chip;
struct gpiod_line;

namespace palpa::hal::linux_gpio {

/// Opens the chip (by name, label, path or number) and gets the line, not yet requested. nullptr
/// with *error naming the spec, the chip or line and the reason; on success *chip is open.
gpiod_line* FindGpioLine(const std::string& spec, gpiod_chip** chip, std::string* error);

}  // namespace palpa::hal::linux_gpio
