// Deadline-paced periodic tick (as modm's PeriodicTimer): the next deadline is the previous one
// plus the period, so jitter never accumulates; missed periods are counted, not replayed.
#pragma once

#include <cstdint>

namespace palpa::core {

struct TickStats {
  uint64_t ticks = 0;
  uint32_t overruns = 0;       ///< periods skipped because a tick started too late
  uint32_t jitter_max_us = 0;  ///< largest lateness of a tick start against its deadline
  uint32_t worst_tick_us = 0;  ///< longest tick duration
  uint64_t busy_us = 0;        ///< sum of tick durations (mean = busy_us / ticks)
};

class TickPacer {
 public:
  explicit TickPacer(uint32_t period_us) : period_us_(period_us) {}

  void Start(uint64_t now_us) { deadline_us_ = now_us; }

  /// True when a tick is due at now_us.
  bool Due(uint64_t now_us) const { return now_us >= deadline_us_; }

  /// Call at the start of a due tick: records lateness, advances the deadline and counts the
  /// periods missed entirely.
  void BeginTick(uint64_t now_us) {
    const uint64_t late = now_us - deadline_us_;
    if (late > stats_.jitter_max_us)
      stats_.jitter_max_us = static_cast<uint32_t>(late > 0xFFFFFFFFu ? 0xFFFFFFFFu : late);
    deadline_us_ += period_us_;
    if (now_us >= deadline_us_) {
      const uint64_t missed = (now_us - deadline_us_) / period_us_ + 1;
      stats_.overruns += static_cast<uint32_t>(missed);
      deadline_us_ += missed * period_us_;
    }
    started_us_ = now_us;
    ++stats_.ticks;
  }

  /// Call when the tick has written its outputs.
  void EndTick(uint64_t now_us) {
    const uint64_t took = now_us - started_us_;
    stats_.busy_us += took;
    if (took > stats_.worst_tick_us) stats_.worst_tick_us = static_cast<uint32_t>(took);
  }

  uint64_t deadline_us() const { return deadline_us_; }
  uint32_t period_us() const { return period_us_; }
  const TickStats& stats() const { return stats_; }

 private:
  uint32_t period_us_;
  uint64_t deadline_us_ = 0;
  uint64_t started_us_ = 0;
  TickStats stats_{};
};

}  // namespace palpa::core
