// Identification sweep design.
#include "palpa/calibration/sweep.h"

#include <cmath>

namespace palpa::calibration {
namespace {

void Ramp(std::vector<double>& out, double from, double to, double step) {
  const int n = static_cast<int>(std::ceil(std::fabs(to - from) / step));
  for (int k = 1; k <= n; ++k) out.push_back(from + (to - from) * k / n);
}

}  // namespace

std::vector<double> SweepDrives(const SweepPlan& plan) {
  std::vector<double> drives{0};
  Ramp(drives, 0, plan.drive_max, plan.step);
  Ramp(drives, plan.drive_max, 0, plan.step);
  // Turning points close in on the middle: 0 → 90 % → 10 % → 80 % → 20 % ... → back to 0.
  double at = 0;
  for (int k = 1; k <= plan.nested_loops; ++k) {
    const double high = plan.drive_max * (1.0 - 0.1 * k);
    const double low = plan.drive_max * 0.1 * k;
    if (high <= low) break;
    Ramp(drives, at, high, plan.step);
    Ramp(drives, high, low, plan.step);
    at = low;
  }
  Ramp(drives, at, 0, plan.step);
  return drives;
}

}  // namespace palpa::calibration
