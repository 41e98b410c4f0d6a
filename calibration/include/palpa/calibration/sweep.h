// The identification sweep: a quasi-static drive staircase that starts vented, runs the major
// loop and then nested reversals closing in on mid-range, so minor loops are in the data.
#pragma once

#include <vector>

namespace palpa::calibration {

struct SweepPlan {
  double drive_max = 100000;  ///< Pa (pressure, or vacuum magnitude)
  double step = 2500;         ///< Pa between settled points
  int nested_loops = 4;       ///< reversal pairs after the major loop
};

/// Setpoints (Pa ≥ 0) in the order they are applied; each is held for the dwell before reading.
std::vector<double> SweepDrives(const SweepPlan& plan);

}  // namespace palpa::calibration
