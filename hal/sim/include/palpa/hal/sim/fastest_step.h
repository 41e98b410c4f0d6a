// The plant's own fastest possible step on a line: what no controller can beat, because the
// regulator's valve cannot open further. Freestanding.
#pragma once

#include "palpa/hal/sim/regulator_line.h"

namespace palpa::sim {

struct FastestStepResult {
  float dead_time_s = 0;   ///< the regulator's: nothing moves before it
  float reach_s = -1;      ///< command → chamber within 2 % of the step of its target (first)
  float settle_s = -1;     ///< … and staying there while the regulator holds the target
  float overshoot_pa = 0;  ///< beyond the target, in the step's direction, after the valve closed
};

/// Receives the chamber's pressure along a fastest step (for charts).
class FastestStepTrace {
 public:
  virtual void Point(float time_s, float chamber_pa) = 0;

 protected:
  ~FastestStepTrace() = default;
};

/// From rest at `from_pa`, the command changes to `to_pa` (gauge; a vacuum line's are ≤ 0): after
/// the dead time the main valve opens fully towards the target and stays open until the chamber
/// reaches it (or is within 0.5 % of the step, for a target the flow only approaches, such as
/// atmosphere); then the regulator holds the target with its pilot on it. Times from the command;
/// -1 when not within `limit_s`. Stepped at 0.1 ms.
FastestStepResult FastestStep(const RegulatorSetup& setup, float from_pa, float to_pa,
                              float limit_s = 30.0f, FastestStepTrace* trace = nullptr);

}  // namespace palpa::sim
