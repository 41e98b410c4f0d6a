// The demo's chart: the simulator's true outputs and the targets of both passes, deformation and
// stiffness in a panel each, the calibration between the passes left out.
#pragma once

#include <string>
#include <vector>

#include "palpa/host/sim_truth.h"
#include "palpa/host/svg_chart.h"

namespace palpa::cli {

/// What the two passes leave for the chart (board time in s).
struct DemoTraces {
  std::vector<host::TruthReader::Sample> samples;  ///< the simulator's truth, the whole run
  std::vector<host::Series> targets, second;       ///< per finger: pass 1's and pass 2's targets
  bool calibrated = false;                         ///< a second pass ran
  double first_pass_end_s = 0, second_pass_s = 0;
  /// The board time spent calibrating, left out of the chart (0 without a second pass).
  double CutS() const { return calibrated ? second_pass_s - first_pass_end_s - 2 : 0; }
};

/// The SVG drawing (two panels, the cut marked).
std::string DemoChartSvg(DemoTraces traces);

}  // namespace palpa::cli
