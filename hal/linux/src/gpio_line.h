// Finds the line a "CHIP:LINE" spec names (libgpiod v1), shared by the output and input classes.
#pragma once

#include <string>

#include "palpa/hal/linux/opened.h"

struct gpiod_chip;
struct gpiod_line;

namespace palpa::hal::linux_gpio {

struct FoundLine {
  gpiod_chip* chip = nullptr;  ///< open: the caller closes it
  gpiod_line* line = nullptr;  ///< not yet requested
};

/// Opens the chip (by name, label, path or number) and gets the line. A failure names the spec,
/// the chip or line and the reason: kBadValue for a spec that is not CHIP:LINE, kNotFound for a
/// chip or line that is not there; nothing is left open.
Opened<FoundLine> FindGpioLine(const std::string& spec);

}  // namespace palpa::hal::linux_gpio
