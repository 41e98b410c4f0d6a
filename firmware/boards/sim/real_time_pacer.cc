// palpa-sim's real-time pacing: virtual time from real time, slips, batched wakes, late wakes, the
// hold near the host-silence deadline and the host's silence judged in running time.
#include "real_time_pacer.h"

namespace palpa::sim {

RealTimePacer::RealTimePacer(double speed) : speed_(speed), pace_(speed) {}

uint32_t RealTimePacer::steps_per_wake() const {
  const double fit = kWakeUs * pace_ / static_cast<double>(kStepUs);
  const double cap = static_cast<double>(kMaxBatchUs / kStepUs);
  return fit < 1 ? 1 : static_cast<uint32_t>(fit < cap ? fit : cap);
}

void RealTimePacer::Rebase(double wall_us, uint64_t virtual_us) {
  anchor_wall_us_ = wall_us;
  anchor_virtual_us_ = virtual_us;
}

uint64_t RealTimePacer::Target(double wall_us, uint64_t now_us) {
  const double scaled = (wall_us - anchor_wall_us_) * pace_;
  const uint64_t target = anchor_virtual_us_ + (scaled > 0 ? static_cast<uint64_t>(scaled) : 0);
  if (target <= now_us + kMaxLagUs) return target;
  Rebase(wall_us, now_us + kStepUs);  // the slip
  return now_us + kStepUs;
}

double RealTimePacer::WaitUs(double wall_us, uint64_t now_us) const {
  const uint64_t due_us = (now_us / kStepUs + steps_per_wake()) * kStepUs;
  const double ahead =
      due_us > anchor_virtual_us_ ? static_cast<double>(due_us - anchor_virtual_us_) : 0.0;
  const double wait = anchor_wall_us_ + ahead / pace_ - wall_us;
  return wait > 0 ? wait : 0;
}

void RealTimePacer::Woke(double slept_wall_us, double wait_us, double wall_us) {
  const double late = wall_us - (slept_wall_us + wait_us + kLateUs);
  if (late > 0) late_us_ += late;
}

void RealTimePacer::HoldToRealTime(bool hold, double wall_us, uint64_t now_us) {
  const double pace = hold && speed_ > 1 ? 1.0 : speed_;
  if (pace == pace_) return;
  // Continue from where the board is: virtual time neither jumps nor is repeated.
  Rebase(wall_us, now_us);
  pace_ = pace;
}

bool HostNearSilenceTimeout(bool session_open, uint64_t now_us, uint64_t last_host_frame_us,
                            uint32_t host_timeout_us) {
  if (!session_open || now_us < last_host_frame_us) return false;
  const uint64_t silent_us = now_us - last_host_frame_us;
  return silent_us > host_timeout_us / 2 && silent_us <= host_timeout_us;
}

uint64_t HostSilenceLimitUs(bool session_open, uint64_t last_host_frame_us,
                            uint32_t host_timeout_us, double silent_running_us) {
  if (!session_open || silent_running_us >= static_cast<double>(host_timeout_us)) return UINT64_MAX;
  return last_host_frame_us + host_timeout_us;  // the board faults only once past this
}

}  // namespace palpa::sim
