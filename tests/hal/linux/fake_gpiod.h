// A fake libgpiod (v1) for the link-time seam: chips and lines the test declares, every request
// and value written logged in order; errors injected by name.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace palpa::testing::fake_gpiod {

struct State {
  std::set<std::string> chips;  ///< chips that exist (by name, e.g. "gpiochip0")
  unsigned lines_per_chip = 32;
  std::set<std::string> busy;    ///< "gpiochip0:17": requested by someone else
  std::vector<std::string> log;  ///< "request gpiochip0:17=1", "set gpiochip0:17=0", "release ..."
  int open_chips = 0;
};
State& state();
void Reset();

}  // namespace palpa::testing::fake_gpiod
