// The fake libgpiod in a palpa-linux-board process the test drives from outside: the chips it
// declares come from PALPA_FAKE_GPIOD_CHIPS ("gpiochip0,gpiochip1"), and writes to the line
// PALPA_FAKE_GPIOD_FAIL_ON_SIGUSR1 names ("gpiochip0:17") fail from the first SIGUSR1 on, and
// reads of the line PALPA_FAKE_GPIOD_UNREADABLE names fail from the start.
#include <csignal>
#include <cstdlib>
#include <sstream>
#include <string>

#include "fake_gpiod.h"

namespace fg = palpa::testing::fake_gpiod;

namespace {

void Arm(int) { fg::unwritable_armed = 1; }

[[maybe_unused]] const bool g_declared = [] {
  if (const char* chips = std::getenv("PALPA_FAKE_GPIOD_CHIPS")) {
    std::stringstream list(chips);
    for (std::string chip; std::getline(list, chip, ',');) fg::state().chips.insert(chip);
  }
  if (const char* line = std::getenv("PALPA_FAKE_GPIOD_UNREADABLE"))
    fg::state().broken.insert(line);
  if (const char* line = std::getenv("PALPA_FAKE_GPIOD_FAIL_ON_SIGUSR1")) {
    fg::state().unwritable.insert(line);
    fg::unwritable_armed = 0;
    std::signal(SIGUSR1, Arm);
  }
  return true;
}();

}  // namespace
