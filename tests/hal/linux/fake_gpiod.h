// A fake libgpiod (v1) for the link-time seam: chips and lines the test declares, every request
// and value written logged in order; input levels and edge events set by the test; errors injected
// by name.
#pragma once

#include <csignal>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <vector>

struct gpiod_line;

namespace palpa::testing::fake_gpiod {

struct State {
  std::set<std::string> chips;  ///< chips that exist (by name, e.g. "gpiochip0")
  unsigned lines_per_chip = 32;
  std::set<std::string> busy;    ///< "gpiochip0:17": requested by someone else
  std::vector<std::string> log;  ///< "request gpiochip0:17=1", "set gpiochip0:17=0", "release ..."
  int open_chips = 0;
  // Inputs with edge events: each line's electrical level now and the edges still queued as the
  // kernel stamped them (true: rising); reported in the line's sense, as the kernel does.
  std::map<std::string, int> levels;
  std::map<std::string, std::deque<bool>> edges;
  std::set<std::string> broken;          ///< reads of these lines fail (EIO)
  std::set<std::string> unwritable;      ///< writes to these lines fail (EIO), the level kept
  std::vector<gpiod_line*> event_lines;  ///< every line got from an open chip (fd to line)
};
State& state();
void Reset();

/// The `unwritable` lines fail only while this is set (it is unless a test clears it): a process
/// driven from outside arms the failure from a signal handler (fake_gpiod_process.cc).
extern volatile std::sig_atomic_t unwritable_armed;

}  // namespace palpa::testing::fake_gpiod
