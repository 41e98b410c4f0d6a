// palpa-linux-board's real-time footing: SCHED_FIFO and locked memory when permitted, a 1 kHz
// grid of absolute deadlines on CLOCK_MONOTONIC.
#pragma once

#include <cstdint>
#include <string>

namespace palpa::linux_board {

/// What the process got: each part asked for and, when refused, why (started anyway).
struct RealTimeReport {
  bool fifo = false, locked = false;
  std::string fifo_why, locked_why;
  std::string Describe(int priority) const;
};
/// Locks current and future memory (no page fault in a tick) and, with `priority` > 0, asks for
/// SCHED_FIFO at that priority. Neither is required: without them the tick statistics show it.
RealTimeReport EnterRealTime(int priority);

/// Absolute deadlines `period_ns` apart from `start_ns` (CLOCK_MONOTONIC). A late wake skips the
/// periods it missed: the loop never runs a burst of ticks to catch up (the core counts them as
/// overruns).
class DeadlineGrid {
 public:
  DeadlineGrid(uint64_t start_ns, uint64_t period_ns) : next_ns_(start_ns), period_ns_(period_ns) {}
  /// Sleeps until the next deadline (clock_nanosleep, TIMER_ABSTIME); false when a signal woke it.
  bool Sleep();
  /// The deadline after `now_ns` on the grid.
  void Advance(uint64_t now_ns);
  uint64_t next_ns() const { return next_ns_; }

 private:
  uint64_t next_ns_;
  uint64_t period_ns_;
};
uint64_t MonotonicNs();

}  // namespace palpa::linux_board
