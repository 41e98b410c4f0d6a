// Play operators on the host, in double: the regressors of identification and the forward model
// that reports its residuals. Same conventions as the firmware compensator (memory of a vented
// chamber: every operator on its upper clamp at 0 Pa).
#pragma once

#include <vector>

namespace palpa::calibration {

/// Thresholds spread evenly over [0, drive_max / 2): one-sided drive never moves an operator
/// whose threshold is half the range or more.
std::vector<double> EvenThresholds(int operators, double drive_max);

/// z_i[k] for every sample k of a drive sequence that starts vented: rows = samples.
std::vector<std::vector<double>> PlayOutputs(const std::vector<double>& drive,
                                             const std::vector<double>& thresholds);

/// y = offset + S(w0·u + Σ w_i z_i), S(v) = v + Σ g_k max(v − d_k, 0).
struct PlayModel {
  double offset = 0;
  double w0 = 0;
  std::vector<double> thresholds, weights;
  std::vector<double> dead_zones, gains;

  double OutputMap(double v) const;
  /// Outputs along a drive sequence that starts vented.
  std::vector<double> Simulate(const std::vector<double>& drive) const;
};

}  // namespace palpa::calibration
