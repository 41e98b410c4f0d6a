// The finger step's body, inlined into the board's loop over the fingers (a call per finger per
// tick otherwise); StepFinger (finger.cc) is the same step for everyone else.
#pragma once

#include "compensator_step.h"
#include "palpa/core/finger.h"

namespace palpa::core {
namespace finger_step {

/// Before following targets: pneumatic fingers vented, jamming fingers with the vacuum released
/// and the bias on, so the air cushion re-flattens the granules and the compensator starts from
/// a known state. Out of line: the tick's common path is a homed finger.
[[gnu::noinline]] void StepHoming(const FingerParams& p, FingerState& s, const FingerTick& tick);

}  // namespace finger_step

/// StepFinger's body (finger.h has the contract).
[[gnu::always_inline]] inline void StepFingerInline(const FingerParams& p, FingerState& s,
                                                    float applied_pa, const FingerTick& tick) {
  if (s.phase != HomePhase::kHomed) return finger_step::StepHoming(p, s, tick);
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
      setpoint = p.drive_sign * 0.0f;  // signed like the drive would be (−0 on a vacuum line)
    }
  }
  tick.setpoints[p.driven_line] = setpoint;
  tick.line_status[p.driven_line] = status;
  if (p.bias_line != protocol::kNoLine) tick.setpoints[p.bias_line] = p.bias_pa;
}

}  // namespace palpa::core
