// Play operators on the host, in double: the regressors of identification and the forward model
// that reports its residuals. Same conventions as the firmware compensator (memory of a vented
// chamber: every operator on its upper clamp at 0 Pa).
#pragma once

#include <vector>

namespace palpa::calibration {

/// Thresholds r_i = (drive_max / 2) · i / (operators + 1), i = 1..operators: evenly spaced inside
/// (0, drive_max / 2), the ends left out because neither adds a degree of freedom — an operator
/// with threshold 0 is the drive itself (the model's linear term w0·u), and one whose threshold
/// is half the range or more never moves under a one-sided drive that starts vented.
std::vector<double> EvenThresholds(int operators, double drive_max);

/// z_i[k] for every sample k of a drive sequence that starts vented: rows = samples.
std::vector<std::vector<double>> PlayOutputs(const std::vector<double>& drive,
                                             const std::vector<double>& thresholds);

/// How many of the operators add a degree of freedom on this drive sequence to the offset, the
/// drive itself and each other — the columns of the identification's regression. A staircase
/// cannot tell apart operators whose thresholds are close against its step (on 10 kPa steps an
/// operator at 3 and one at 4 kPa move alike), nor one at 0 (the drive) or at half the range.
int DistinctOperators(const std::vector<double>& drive, const std::vector<double>& thresholds);

/// The most operators, up to `most`, whose EvenThresholds this drive sequence tells apart (every
/// one adding a degree of freedom).
int OperatorsToldApart(const std::vector<double>& drive, double drive_max, int most);

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
