// Regulator and chamber: static map with play, dead time, first-order lags. Float only.
#include "palpa/hal/sim/regulator_line.h"

namespace palpa::sim {
namespace {

float Clamp(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

}  // namespace

RegulatorLine::RegulatorLine(const RegulatorSetup& setup, float step_s) : setup_(setup) {
  lag_alpha_ = setup.lag_tau_s > 0 ? step_s / (setup.lag_tau_s + step_s) : 1.0f;
  chamber_alpha_ = setup.chamber_tau_s > 0 ? step_s / (setup.chamber_tau_s + step_s) : 1.0f;
  constexpr float kDumpTauS = 0.05f;  // the dump valve vents the chamber directly
  vent_alpha_ = step_s / (kDumpTauS + step_s);
  const float steps = step_s > 0 ? setup.dead_time_s / step_s + 0.5f : 0.0f;
  delay_steps_ =
      static_cast<uint8_t>(steps >= kMaxRegulatorDelaySteps ? kMaxRegulatorDelaySteps - 1 : steps);
}

float RegulatorLine::StaticOutput(float magnitude) const {
  const RegulatorErrors& e = setup_.errors;
  const float fs = setup_.full_scale_pa;
  const float x = Clamp(magnitude / fs, 0.0f, 1.0f);
  // Linearity error: a bow, zero at both ends, largest mid-scale (4x(1-x) peaks at 1).
  const float bow = e.linearity_pa * 4.0f * x * (1.0f - x);
  return Clamp((1.0f + e.gain) * magnitude + e.offset_pa + bow, 0.0f, fs);
}

void RegulatorLine::Step(float command_pa, bool vented) {
  if (vented) {
    outlet_ += vent_alpha_ * (0.0f - outlet_);
    chamber_ += vent_alpha_ * (0.0f - chamber_);
    for (float& d : delay_) d = 0;
    return;
  }
  // The regulator only makes pressure of its own sign; a command the other way means 0.
  const float magnitude = Clamp(command_pa * setup_.sign, 0.0f, setup_.full_scale_pa);
  // Hysteresis and sensitivity: the command must move past the play before the output follows.
  const float r = setup_.errors.play_pa;
  if (magnitude > play_ + r) play_ = magnitude - r;
  if (magnitude < play_ - r) play_ = magnitude + r;
  float target = magnitude < setup_.min_set_pa ? 0.0f : StaticOutput(play_ < 0 ? 0 : play_);
  target *= setup_.sign;
  if (!setup_.dynamics) {
    outlet_ = chamber_ = target;
    return;
  }
  float delayed = target;
  if (delay_steps_ > 0) {
    delayed = delay_[delay_index_];
    delay_[delay_index_] = target;
    delay_index_ = static_cast<uint8_t>((delay_index_ + 1) % delay_steps_);
  }
  if (leak_ > 0) {
    // Outlet droop of one tubing-flow unit per unit (an assumption: the regulator's output
    // resistance is about the tubing's); the leak drains the chamber toward 0.
    outlet_ += lag_alpha_ * (delayed - (outlet_ - chamber_) - outlet_);
    chamber_ += chamber_alpha_ * (outlet_ - chamber_) - chamber_alpha_ * leak_ * chamber_;
    return;
  }
  outlet_ += lag_alpha_ * (delayed - outlet_);
  chamber_ += chamber_alpha_ * (outlet_ - chamber_);
}

}  // namespace palpa::sim
