// Host-side play operators and the forward PI / asymmetric PI model.
#include "palpa/calibration/play_operators.h"

#include <algorithm>

namespace palpa::calibration {

std::vector<double> EvenThresholds(int operators, double drive_max) {
  std::vector<double> r(static_cast<size_t>(operators));
  for (int i = 0; i < operators; ++i) r[static_cast<size_t>(i)] = 0.5 * drive_max * i / operators;
  return r;
}

std::vector<std::vector<double>> PlayOutputs(const std::vector<double>& drive,
                                             const std::vector<double>& thresholds) {
  std::vector<double> z = thresholds;  // vented
  std::vector<std::vector<double>> rows;
  rows.reserve(drive.size());
  for (double u : drive) {
    for (size_t i = 0; i < z.size(); ++i)
      z[i] = std::clamp(z[i], u - thresholds[i], u + thresholds[i]);
    rows.push_back(z);
  }
  return rows;
}

double PlayModel::OutputMap(double v) const {
  double s = v;
  for (size_t k = 0; k < dead_zones.size(); ++k) s += gains[k] * std::max(v - dead_zones[k], 0.0);
  return s;
}

std::vector<double> PlayModel::Simulate(const std::vector<double>& drive) const {
  const auto z = PlayOutputs(drive, thresholds);
  std::vector<double> y(drive.size());
  for (size_t k = 0; k < drive.size(); ++k) {
    double v = w0 * drive[k];
    for (size_t i = 0; i < weights.size(); ++i) v += weights[i] * z[k][i];
    y[k] = offset + OutputMap(v);
  }
  return y;
}

}  // namespace palpa::calibration
