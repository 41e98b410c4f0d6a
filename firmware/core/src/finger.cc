// Fingers in target mode: homing, then the compensator maps targets to line setpoints.
#include "palpa/core/finger.h"

#include "palpa/core/curve.h"

namespace palpa::core {

FingerParams MakeFingerParams(const protocol::ConfigureFinger& finger, float drive_limit_pa) {
  FingerParams p;
  p.kind = finger.kind;
  p.compensator = finger.compensator;
  p.line_a = finger.line_a;
  p.line_b = finger.line_b;
  p.driven_line = finger.line_b != protocol::kNoLine ? finger.line_b : finger.line_a;
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

FingerOutput StepFinger(const FingerParams& p, FingerState& s, uint64_t now_us,
                        uint32_t home_dwell_us, float applied_pa) {
  FingerOutput out;
  const bool jamming = p.kind == protocol::FingerKind::kJamming;
  if (s.phase == HomePhase::kNeedsHoming) {
    s.phase = HomePhase::kHoming;
    s.homed_at_us = now_us + home_dwell_us;
  }
  // The drive domain is ≥ 0: chamber pressure, or vacuum magnitude on a jamming finger.
  const float applied_drive = jamming ? -applied_pa : applied_pa;
  if (s.phase == HomePhase::kHoming) {
    // Pneumatic: vented. Jamming: vacuum released with the bias on, so the air cushion
    // re-flattens the granules before the compensator starts from a known state.
    out.setpoint_a = jamming ? p.bias_pa : 0.0f;
    out.setpoint_b = 0;
    out.homing = true;
    if (now_us >= s.homed_at_us) {
      s.phase = HomePhase::kHomed;
      HomeCompensator(p.compensation, s.memory);
    }
    return out;
  }
  float setpoint = 0;
  if (p.compensator == protocol::CompensatorKind::kNone) {
    setpoint = StaticInverse(p, s.target);
  } else {
    // Memory follows the applied drive every tick, also while the target is 0 (venting).
    const CompensatorOutput c = StepCompensator(p.compensation, s.memory, s.target, applied_drive);
    const float drive = s.target > 0 ? c.drive : 0.0f;  // "off" is 0 Pa whatever the model says
    out.saturated = s.target > 0 && c.saturated;
    setpoint = jamming ? -drive : drive;
  }
  if (jamming) {
    out.setpoint_a = p.bias_pa;
    out.setpoint_b = setpoint;
  } else {
    out.setpoint_a = setpoint;
  }
  return out;
}

}  // namespace palpa::core
