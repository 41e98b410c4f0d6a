// The fastest step: full flow until the target, then hold.
#include "palpa/hal/sim/fastest_step.h"

namespace palpa::sim {
namespace {

float Abs(float v) { return v < 0 ? -v : v; }

}  // namespace

FastestStepResult FastestStep(const RegulatorSetup& setup, float from_pa, float to_pa,
                              float limit_s, FastestStepTrace* trace) {
  constexpr float kStepS = 1e-4f;
  FastestStepResult r;
  r.dead_time_s = setup.dead_time_s;
  LineFlow line(setup.flow, kStepS);
  line.Preset(from_pa);
  const float step = to_pa - from_pa;
  const float band = 0.02f * Abs(step);
  const float direction = (step > 0 ? 1.0f : -1.0f) * setup.flow.sign;  // valve opening's sign
  const int dead = static_cast<int>(setup.dead_time_s / kStepS + 0.5f);
  const int limit = static_cast<int>(limit_s / kStepS);
  bool open = Abs(step) > 0;
  int last_outside = -1;
  for (int i = 0; i < limit; ++i) {
    const float chamber = line.chamber_pa();
    if (trace != nullptr && i % 10 == 0) trace->Point(static_cast<float>(i) * kStepS, chamber);
    if (i < dead) {
      line.Step(from_pa, false);
      last_outside = i;
      continue;
    }
    const float short_of = (to_pa - chamber) * (step > 0 ? 1.0f : -1.0f);  // > 0: not there yet
    if (open && short_of <= 0.005f * Abs(step)) open = false;
    if (open) {
      line.StepOpen(direction);
    } else {
      line.Step(to_pa, false);
    }
    const float after = line.chamber_pa();
    if (Abs(after - to_pa) > band) {
      last_outside = i;
    } else if (r.reach_s < 0) {
      r.reach_s = static_cast<float>(i + 1) * kStepS;
    }
    const float beyond = (after - to_pa) * (step > 0 ? 1.0f : -1.0f);
    if (!open && beyond > r.overshoot_pa) r.overshoot_pa = beyond;
    // Settled: inside the band for a second after the valve closed, with the valve holding.
    if (!open && r.reach_s >= 0 && i - last_outside > static_cast<int>(1.0f / kStepS)) break;
  }
  if (r.reach_s >= 0 && limit - last_outside > static_cast<int>(1.0f / kStepS))
    r.settle_s = static_cast<float>(last_outside + 2) * kStepS;
  return r;
}

}  // namespace palpa::sim
