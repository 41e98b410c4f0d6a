// Fingers in target mode: homing, then the compensator maps targets to line setpoints.
#include "palpa/core/finger.h"

#include "compensator_step.h"
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

namespace {

/// Before following targets: pneumatic fingers vented, jamming fingers with the vacuum released
/// and the bias on, so the air cushion re-flattens the granules and the compensator starts from
/// a known state. Out of line: the tick's common path is a homed finger.
[[gnu::noinline]] void StepHoming(const FingerParams& p, FingerState& s, const FingerTick& tick) {
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

}  // namespace

void StepFinger(const FingerParams& p, FingerState& s, float applied_pa, const FingerTick& tick) {
  if (s.phase != HomePhase::kHomed) return StepHoming(p, s, tick);
  float setpoint = 0;
  uint8_t status = 0;
  if (p.compensator == protocol::CompensatorKind::kNone) {
    setpoint = StaticInverse(p, s.target);  // the curve holds line pressures, signs included
  } else {
    // Memory follows the applied drive every tick, also while the target is 0 (venting). The
    // play models (pi, api) run inline: they are the loop-rate cost of a compensated finger.
    const float applied = p.drive_sign * applied_pa;
    bool saturated = false;
    float drive = 0;
    if (p.compensator == protocol::CompensatorKind::kBranch) {
      const CompensatorOutput c = StepCompensator(p.compensation, s.memory, s.target, applied);
      drive = c.drive;
      saturated = c.saturated;
    } else {
      drive = StepPlayInline(p.compensation, s.memory, s.target, applied, saturated);
    }
    if (s.target > 0) {  // "off" is 0 Pa whatever the model says
      setpoint = p.drive_sign * drive;
      if (saturated) status = protocol::line_status::kSaturated;
    } else {
      setpoint = p.drive_sign * 0.0f;
    }
  }
  tick.setpoints[p.driven_line] = setpoint;
  tick.line_status[p.driven_line] = status;
  if (p.bias_line != protocol::kNoLine) tick.setpoints[p.bias_line] = p.bias_pa;
}

}  // namespace palpa::core
