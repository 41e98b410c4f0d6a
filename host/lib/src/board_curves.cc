// The board's static inverse as the host's curve, and a calibration file's distance from it.
#include "palpa/host/board_curves.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>
#include <vector>

namespace palpa::host {
namespace {

using Points = std::vector<std::pair<double, double>>;  // (drive Pa, output), drive ascending

Points BoardPoints(const protocol::ConfigureFinger& f) {
  Points p;
  for (uint8_t i = 0; i < f.inverse_count && i < f.inverse.size(); ++i)
    p.emplace_back(f.inverse[i].setpoint_pa, f.inverse[i].output);
  std::sort(p.begin(), p.end());
  return p;
}

/// Linear interpolation inside [front, back] (callers stay inside).
double At(const Points& p, double drive) {
  for (size_t i = 1; i < p.size(); ++i) {
    if (drive <= p[i].first || i + 1 == p.size()) {
      const double span = p[i].first - p[i - 1].first;
      const double f = span != 0 ? std::clamp((drive - p[i - 1].first) / span, 0.0, 1.0) : 1;
      return p[i - 1].second + f * (p[i].second - p[i - 1].second);
    }
  }
  return p.front().second;
}

/// The nominal curves' output at a drive, in the board's unit (µm or mN/mm).
double NominalOutput(const FingerCurves& c, protocol::FingerKind kind, double pa) {
  const double kpa = pa / 1000;
  if (kind == protocol::FingerKind::kJamming)
    return 1000 * (c.stiffness_at_0 + (c.stiffness_at_full_vacuum - c.stiffness_at_0) * -kpa / 100);
  return 1000 * std::max(0.0, c.deformation_slope_mm_per_kpa * kpa + c.deformation_intercept_mm);
}

}  // namespace

bool IsNominalInverse(const protocol::ConfigureFinger& finger) {
  if (finger.inverse_count < 2) return false;
  const FingerCurves nominal;
  const Points p = BoardPoints(finger);
  // The compiled-in inverse rounds its setpoints to whole Pa: a µm and a half at most.
  return std::all_of(p.begin(), p.end(), [&](const auto& q) {
    return std::abs(NominalOutput(nominal, finger.kind, q.first) - q.second) <= 1.5;
  });
}

FingerCurves CurvesFromBoard(const protocol::ConfigureFinger& finger, const std::string& source) {
  FingerCurves curves;
  curves.source = source;
  if (IsNominalInverse(finger) || finger.inverse_count < 2) return curves;
  // In the inverse's order, as a calibration file's curve is (it is written from the inverse).
  for (uint8_t i = 0; i < finger.inverse_count; ++i) {
    curves.calibrated.emplace_back(finger.inverse[i].setpoint_pa / 1000.0,
                                   finger.inverse[i].output / 1000.0);
  }
  if (finger.kind == protocol::FingerKind::kJamming) {
    curves.stiffness_at_0 = curves.calibrated.front().second;
    curves.stiffness_at_full_vacuum = curves.calibrated.back().second;
  } else {
    curves.max_deformation_mm = curves.calibrated.back().second;
  }
  return curves;
}

CurveComparison CompareWithBoard(const CalibrationFile& file,
                                 const protocol::ConfigureFinger& board) {
  CurveComparison c;
  Points from_file;
  for (const CurvePoint& q : file.curve) from_file.emplace_back(q.drive_pa, q.output);
  std::sort(from_file.begin(), from_file.end());
  const Points from_board = BoardPoints(board);
  if (from_file.size() < 2 || from_board.size() < 2) return c;
  const double lo = std::max(from_file.front().first, from_board.front().first);
  const double hi = std::min(from_file.back().first, from_board.back().first);
  if (lo > hi) return c;
  c.overlap = true;
  std::vector<double> drives = {lo, hi};
  for (const Points* p : std::initializer_list<const Points*>{&from_file, &from_board})
    for (const auto& q : *p)
      if (q.first > lo && q.first < hi) drives.push_back(q.first);
  for (const double d : drives) {
    const double diff = std::abs(At(from_file, d) - At(from_board, d));
    if (diff > c.disagreement) c.disagreement = diff, c.at_pa = d;
  }
  return c;
}

double CurveTolerance(const CalibrationFile& file) {
  return std::max(1.0, file.quality.residual_rms);
}

}  // namespace palpa::host
