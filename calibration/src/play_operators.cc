// Host-side play operators and the forward PI / asymmetric PI model.
#include "palpa/calibration/play_operators.h"

#include <algorithm>
#include <cmath>

namespace palpa::calibration {

std::vector<double> EvenThresholds(int operators, double drive_max) {
  std::vector<double> r(static_cast<size_t>(operators));
  for (int i = 0; i < operators; ++i)
    r[static_cast<size_t>(i)] = 0.5 * drive_max * (i + 1) / (operators + 1);
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

int DistinctOperators(const std::vector<double>& drive, const std::vector<double>& thresholds) {
  // Gram–Schmidt over the columns, twice against each earlier one (for round-off): a column
  // adds a degree of freedom when a share of it is left. On the sweeps palpa uses, independent
  // columns keep at least 5e-4 of their norm and dependent ones under 1e-7.
  constexpr double kShareLeft = 1e-5;
  const auto z = PlayOutputs(drive, thresholds);
  std::vector<std::vector<double>> basis;
  int distinct = 0;
  auto add = [&](std::vector<double> column) {
    double norm = 0;
    for (double v : column) norm += v * v;
    for (int pass = 0; pass < 2; ++pass) {
      for (const auto& b : basis) {
        double dot = 0;
        for (size_t k = 0; k < column.size(); ++k) dot += column[k] * b[k];
        for (size_t k = 0; k < column.size(); ++k) column[k] -= dot * b[k];
      }
    }
    double left = 0;
    for (double v : column) left += v * v;
    if (norm <= 0 || std::sqrt(left / norm) <= kShareLeft) return false;
    for (double& v : column) v /= std::sqrt(left);
    basis.push_back(std::move(column));
    return true;
  };
  add(std::vector<double>(drive.size(), 1.0));  // the offset
  add(drive);                                   // w0·u
  for (size_t i = 0; i < thresholds.size(); ++i) {
    std::vector<double> column;
    for (const auto& row : z) column.push_back(row[i]);
    if (add(std::move(column))) ++distinct;
  }
  return distinct;
}

int OperatorsToldApart(const std::vector<double>& drive, double drive_max, int most) {
  for (int n = most; n > 0; --n) {
    if (DistinctOperators(drive, EvenThresholds(n, drive_max)) == n) return n;
  }
  return 0;
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
