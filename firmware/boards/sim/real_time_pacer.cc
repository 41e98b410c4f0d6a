// palpa-sim's real-time pacing: virtual time from real time, slips, and batched wakes.
#include "real_time_pacer.h"

namespace palpa::sim {

RealTimePacer::RealTimePacer(double speed) : speed_(speed) {
  const double fit = kWakeUs * speed / static_cast<double>(kStepUs);
  const double cap = static_cast<double>(kMaxBatchUs / kStepUs);
  steps_per_wake_ = fit < 1 ? 1 : static_cast<uint32_t>(fit < cap ? fit : cap);
}

uint64_t RealTimePacer::Target(double wall_us, uint64_t now_us) {
  const double scaled = (wall_us - slipped_us_) * speed_;
  const uint64_t target = scaled > 0 ? static_cast<uint64_t>(scaled) : 0;
  if (target <= now_us + kMaxLagUs) return target;
  slipped_us_ += static_cast<double>(target - now_us - kStepUs) / speed_;
  return now_us + kStepUs;
}

double RealTimePacer::WaitUs(double wall_us, uint64_t now_us) const {
  const uint64_t due_us = (now_us / kStepUs + steps_per_wake_) * kStepUs;
  const double wait = static_cast<double>(due_us) / speed_ + slipped_us_ - wall_us;
  return wait > 0 ? wait : 0;
}

}  // namespace palpa::sim
