// palpa-sim's mapping from real time to the board's virtual time: scaled by --speed, slipping
// instead of racing when the process falls behind, waking once per batch of steps.
#pragma once

#include <cstdint>

namespace palpa::sim {

class RealTimePacer {
 public:
  static constexpr uint64_t kStepUs = 1000;     ///< the board's tick, virtual
  static constexpr uint64_t kMaxLagUs = 20000;  ///< virtual time the loop may fall behind
  /// At most this much virtual time per wake: the board reads the host at least this often, far
  /// inside its 100 ms host-silence timeout.
  static constexpr uint64_t kMaxBatchUs = 10000;
  /// Real time a batch aims to fill: one wake per step at real time or slower, and no more than
  /// about a thousand wakes a second at any speed (each wake costs several system calls).
  static constexpr double kWakeUs = 1000;

  /// `speed`: virtual seconds per real second (> 0).
  explicit RealTimePacer(double speed);

  /// Steps the loop lets fall due before it wakes: 1 up to real time, then as many as fit in
  /// kWakeUs of real time, at most kMaxBatchUs of virtual time.
  uint32_t steps_per_wake() const { return steps_per_wake_; }

  /// Virtual time to advance to at `wall_us` of real time (since the start) with the board at
  /// `now_us`. When that is more than kMaxLagUs ahead, the excess is given up (virtual time
  /// slips) and the board is let one step further: racing to catch up would squeeze the host's
  /// real-time heartbeats out of the board's timeout window.
  uint64_t Target(double wall_us, uint64_t now_us);

  /// Real time from `wall_us` until the next wake is due: when steps_per_wake() more steps are
  /// due after `now_us` (0 when they already are).
  double WaitUs(double wall_us, uint64_t now_us) const;

  /// Real time given up to slips so far.
  double slipped_us() const { return slipped_us_; }

 private:
  double speed_;
  uint32_t steps_per_wake_;
  double slipped_us_ = 0;
};

}  // namespace palpa::sim
