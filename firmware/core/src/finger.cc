// Fingers in target mode: homing, then the compensator maps targets to line setpoints.
#include "palpa/core/finger.h"

#include "finger_step.h"
#include "palpa/core/curve.h"

namespace palpa::core {

FingerParams MakeFingerParams(const protocol::ConfigureFinger& finger, float drive_limit_pa) {
  FingerParams p;
  p.kind = finger.kind;
  p.compensator = finger.compensator;
  p.line_a = finger.line_a;
  p.line_b = finger.line_b;
  const bool jamming = finger.kind == protocol::FingerKind::kJamming;
  p.driven_line = finger.line_b != protocol::kNoLine ? finger.line_b : finger.line_a;
  p.bias_line = jamming ? finger.line_a : protocol::kNoLine;
  p.drive_sign = jamming ? -1.0f : 1.0f;
  p.bias_pa = static_cast<float>(finger.bias_pa);
  p.inverse_count = finger.inverse_count;
  for (uint8_t i = 0; i < finger.inverse_count; ++i) {
    p.inverse_output[i] = static_cast<float>(finger.inverse[i].output);
    p.inverse_setpoint[i] = static_cast<float>(finger.inverse[i].setpoint_pa);
  }
  p.max_target = finger.inverse_count > 0 ? finger.inverse[finger.inverse_count - 1].output : 0;
  p.compensation = MakeCompensator(finger, drive_limit_pa);
  return p;
}

protocol::OutputUnit UnitOf(protocol::FingerKind kind) {
  return kind == protocol::FingerKind::kJamming ? protocol::OutputUnit::kStiffnessMilliNewtonPerMm
                                                : protocol::OutputUnit::kDeformationMicrometre;
}

float StaticInverse(const FingerParams& p, float target) {
  if (target <= 0) return 0;  // "off" is 0 Pa, whatever the curve's first point says
  return Interpolate(p.inverse_output.data(), p.inverse_setpoint.data(), p.inverse_count, target);
}

void finger_step::StepHoming(const FingerParams& p, FingerState& s, const FingerTick& tick) {
  if (s.phase == HomePhase::kNeedsHoming) {
    s.phase = HomePhase::kHoming;
    s.homed_at_us = tick.now_us + tick.home_dwell_us;
  }
  tick.setpoints[p.driven_line] = 0;
  tick.line_status[p.driven_line] = 0;
  if (p.bias_line != protocol::kNoLine) tick.setpoints[p.bias_line] = p.bias_pa;
  if (tick.now_us >= s.homed_at_us) {
    s.phase = HomePhase::kHomed;
    HomeCompensator(p.compensation, s.memory);
  }
}

void StepFinger(const FingerParams& p, FingerState& s, float applied_pa, const FingerTick& tick) {
  StepFingerInline(p, s, applied_pa, tick);
}

}  // namespace palpa::core
