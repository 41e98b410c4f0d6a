// palpa-sim's mapping from real time to the board's virtual time: scaled by --speed, slipping
// instead of racing when the process falls behind, waking once per batch of steps, back at real
// time while a host that holds a session has been silent for half its timeout, and never past the
// host-silence deadline before the host has been silent that long in the simulator's running time
// (real time less what palpa-sim waited for the processor).
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

  /// The pace now: --speed, or at most 1 while held to real time.
  double pace() const { return pace_; }
  /// Steps the loop lets fall due before it wakes: 1 up to real time, then as many as fit in
  /// kWakeUs of real time, at most kMaxBatchUs of virtual time.
  uint32_t steps_per_wake() const;

  /// Virtual time to advance to at `wall_us` of real time (since the start) with the board at
  /// `now_us`. When that is more than kMaxLagUs ahead, the excess is given up (virtual time
  /// slips) and the board is let one step further: racing to catch up would squeeze the host's
  /// real-time heartbeats out of the board's timeout window.
  uint64_t Target(double wall_us, uint64_t now_us);

  /// Real time from `wall_us` until the next wake is due: when steps_per_wake() more steps are
  /// due after `now_us` (0 when they already are).
  double WaitUs(double wall_us, uint64_t now_us) const;

  /// Notes the wake at `wall_us` of a loop that went to sleep for `wait_us` (at most) at
  /// `slept_wall_us`. What it woke later than that, beyond kLateUs, it spent waiting for the
  /// processor: that time is not the simulator's running time (below).
  void Woke(double slept_wall_us, double wait_us, double wall_us);
  /// The simulator's running time at `wall_us`: real time less what its wakes came late. The
  /// host's silence is judged on it, as virtual time slips over a late wake: a machine too busy
  /// to run palpa-sim is too busy to run its host, and time in which the board could not look
  /// is no time in which the host could have been heard.
  double RunningUs(double wall_us) const { return wall_us - late_us_; }
  /// A wake this much later than asked for is still on time: the wake itself and a batch's
  /// steps take some real time.
  static constexpr double kLateUs = 2000;

  /// Holds the pace to real time (when --speed is faster) from here on, or releases it. Faster
  /// than real time the host's timeout shrinks in real time with the speed (10 ms at 10x), and a
  /// host that is merely descheduled for that long would lose its session; a host that is gone
  /// still meets the same timeout in board time.
  void HoldToRealTime(bool hold, double wall_us, uint64_t now_us);

 private:
  void Rebase(double wall_us, uint64_t virtual_us);
  double speed_;
  double pace_;
  double anchor_wall_us_ = 0;  ///< real time at which virtual time was anchor_virtual_us_
  uint64_t anchor_virtual_us_ = 0;
  double late_us_ = 0;  ///< real time the loop's wakes came late, summed
};

/// Whether palpa-sim should hold to real time: a session is open and the host has been silent
/// for more than half its timeout, but not yet past it (then the board is safe and has no
/// deadline left to protect).
bool HostNearSilenceTimeout(bool session_open, uint64_t now_us, uint64_t last_host_frame_us,
                            uint32_t host_timeout_us);

/// The latest board time the loop may advance to while a host holds a session: the host's silence
/// is judged in real time as well as in board time. Faster than real time a host that is merely
/// descheduled (a loaded machine: tens of milliseconds between its frames) would otherwise look
/// silent to the board for the whole timeout; held here, the board's deadline (`last_host_frame_us`
/// + the timeout) comes only once `silent_running_us`, the simulator's running time since that
/// frame arrived (RealTimePacer::RunningUs), has reached the timeout too. A host that is gone
/// meets the timeout in real time, as on hardware, while palpa-sim gets the processor.
/// UINT64_MAX when nothing holds the board (no session, or silent in real time for the timeout).
uint64_t HostSilenceLimitUs(bool session_open, uint64_t last_host_frame_us,
                            uint32_t host_timeout_us, double silent_running_us);

}  // namespace palpa::sim
