// A link-time fake of libevdev: a scripted input device whose recorded events are replayed
// through libevdev's own calls, SYN_DROPPED and its resynchronisation included.
#pragma once

#include <linux/input.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace palpa::testing {

/// One step of a recording: an event the device emits, a run of events the kernel drops
/// (the device's state moves, the reader sees SYN_DROPPED then the differences), or the device
/// going away.
struct EvdevStep {
  enum Kind { kEvent, kDropped, kGone } kind = kEvent;
  input_event event{};
  std::vector<input_event> lost;  ///< kDropped: what the kernel dropped
};

struct FakeEvdev {
  std::string name = "Fake Pen Tablet";
  bool evdev = true;  ///< false: libevdev_new_from_fd fails (not an event node)
  std::map<std::pair<unsigned, unsigned>, input_absinfo> abs;  ///< (EV_ABS, code) → axis
  std::vector<std::pair<unsigned, unsigned>> codes;            ///< other (type, code) it has
  std::vector<EvdevStep> script;
  // Replay state (the fake's; reset by Reset()).
  size_t next = 0;
  bool syncing = false;
  std::vector<input_event> pending_sync;
  std::map<std::pair<unsigned, unsigned>, int> device_state, reader_state;
  int clock_id = -1;
  bool freed = false;
};

/// The fake every libevdev call in this test binary reaches.
FakeEvdev& Evdev();
void ResetEvdev();
/// An event at time t seconds.
input_event Ev(double t, unsigned type, unsigned code, int value);
/// A tablet with x 0 … 15200 (100/mm), y 0 … 9500 (100/mm), pressure 0 … 2047 and BTN_TOUCH.
void MakeTablet();
/// One report at time t: x, y, pressure and touch, then SYN_REPORT.
void Report(double t, int x, int y, int pressure, bool touch);

}  // namespace palpa::testing
