// The fastest step a unit's own regulator allows through its command: from the regulator's state
// as a step begins, the command at the line's limit toward the target (bang), then the command
// that holds the target on this unit (its static errors and play included), switched at the best
// of a few points short of the target; optionally with the line's dump valve open through the bang
// of a step toward atmosphere. What no board could beat by what it commands; unlike FastestStep,
// the valve opens only as far as the command takes the pilot past the outlet (a vacuum
// regulator's pilot stops at 0 kPa and at −100 kPa, its valve's band is 10 kPa).
#pragma once

#include <cmath>

#include "palpa/hal/sim/regulator_line.h"
#include "steps_measure.h"

namespace palpa::bench {

struct CommandBound {
  double settle_ms = kNever;  ///< within Band() for good, from the command (kNever: not in 1 s)
  double hold_pa = 0;         ///< the command that holds the target on this unit
  double switch_short = 0;    ///< where the command left the limit: short of the target, × step
};

namespace bound_detail {

/// Runs `r` with `bang_pa` until the chamber is within `switch_pa` of `to_pa` (short of it), then
/// with `hold_pa`, for `ms` ms; returns the last ms outside `band` (or the final chamber).
inline int Run(sim::RegulatorLine r, double to_pa, double direction, double bang_pa,
               double switch_pa, double hold_pa, double band, int ms, double* final_pa,
               bool dump = false) {
  bool bang = switch_pa >= 0;
  int last_outside = 0;
  for (int t = 1; t <= ms; ++t) {
    if (bang && direction * (to_pa - r.chamber_pa()) <= switch_pa) bang = false;
    r.Step(static_cast<float>(bang ? bang_pa : hold_pa), false, bang && dump);
    if (std::fabs(r.chamber_pa() - to_pa) > band) last_outside = t;
  }
  if (final_pa != nullptr) *final_pa = r.chamber_pa();
  return last_outside;
}

}  // namespace bound_detail

/// `start`: the unit's regulator line as the step is commanded; `low_pa`/`high_pa`: the line's
/// command limits; `dump`: the dump valve open through the bang when the step goes toward
/// atmosphere. The hold command is found by bisection so that the chamber ends on the target
/// after the bang (the regulator's play makes it depend on the side the command comes from).
inline CommandBound FastestThroughCommand(const sim::RegulatorLine& start, double from_pa,
                                          double to_pa, double low_pa, double high_pa,
                                          bool dump = false) {
  const double direction = to_pa >= from_pa ? 1 : -1;
  const double bang = direction > 0 ? high_pa : low_pa, step = std::fabs(to_pa - from_pa);
  const double band = Band(from_pa, to_pa);
  dump = dump && std::fabs(to_pa) < std::fabs(from_pa);
  CommandBound b;
  double lo = to_pa - 5000, hi = to_pa + 5000;
  for (int i = 0; i < 20; ++i) {  // the chamber ends monotone in the hold command
    const double mid = 0.5 * (lo + hi);
    double end = 0;
    bound_detail::Run(start, to_pa, direction, bang, 0.005 * step, mid, band, 1500, &end, dump);
    (end < to_pa ? lo : hi) = mid;
  }
  b.hold_pa = 0.5 * (lo + hi);
  for (double x : {0.005, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4}) {
    const int last = bound_detail::Run(start, to_pa, direction, bang, x * step, b.hold_pa, band,
                                       1000, nullptr, dump);
    if (last < 1000 && last < b.settle_ms) b.settle_ms = last, b.switch_short = x;
  }
  return b;
}

}  // namespace palpa::bench
