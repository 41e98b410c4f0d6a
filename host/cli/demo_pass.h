// One pass of the demo's stimuli: each step set on the board, held, and read back from the
// simulator's truth; the errors a pass made, and the two passes side by side.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/sim_truth.h"
#include "palpa/host/svg_chart.h"

namespace palpa::cli {

/// One stimulus: a level per finger, the pneumatic fingers 1-3 or the jamming fingers 4-5.
struct Step {
  std::vector<int> levels;
  bool jamming;
  std::string names;  ///< the levels by their names in the stimulus set
};

/// What one pass of the stimuli measured, pneumatic and jamming fingers apart.
struct PassFigures {
  double worst_pct[2] = {0, 0};  ///< largest |achieved − target| / target (pneumatic, jamming)
  double sum_sq_pct[2] = {0, 0};
  int count[2] = {0, 0};
  /// Pneumatic level 1 reached from level 0 and from level 2: the hysteresis a user feels.
  double l1_from_below = 0, l1_from_above = 0;
  int n_below = 0, n_above = 0;
  double Rms(int k) const { return count[k] > 0 ? std::sqrt(sum_sq_pct[k] / count[k]) : 0; }
};

/// Plays `steps` (levels through `levels`, the device's tables), printing a row each and adding
/// each finger's target to `targets`; false (printed) when the board refuses one.
bool PlaySteps(host::Device& d, host::TruthReader& truth, const host::LevelTables& levels,
               const std::vector<Step>& steps, std::vector<host::Series>& targets,
               PassFigures& figures);

/// The figures of the nominal pass, and of the calibrated one beside them when there is one.
void PrintSummary(const PassFigures& nominal, const PassFigures* calibrated,
                  const std::string& compensator);

}  // namespace palpa::cli
