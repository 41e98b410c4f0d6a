// Branch compensator and static inverse from the major loop of a sweep: monotone (isotonic)
// rising and falling curves, read at evenly spaced output levels.
#include <algorithm>
#include <cmath>

#include "palpa/calibration/hysteresis_fit.h"
#include "palpa/core/compensator.h"
#include "palpa/protocol/compensator_params.h"

namespace palpa::calibration {
namespace {

using protocol::CompensatorKind;

struct Pass {
  std::vector<SweepSample> points;
  bool rising = true;
};

/// Splits a sweep into monotone passes (a reversal is a move against the direction).
std::vector<Pass> Passes(const std::vector<SweepSample>& sweep) {
  std::vector<Pass> passes;
  Pass current;
  for (size_t k = 0; k < sweep.size(); ++k) {
    if (!current.points.empty()) {
      const bool up = sweep[k].drive_pa > current.points.back().drive_pa;
      const bool down = sweep[k].drive_pa < current.points.back().drive_pa;
      if (current.points.size() == 1 && (up || down)) current.rising = up;
      if ((current.rising && down) || (!current.rising && up)) {
        passes.push_back(current);
        Pass next;
        next.points.push_back(current.points.back());  // the turning point starts the next pass
        next.rising = up;
        current = next;
      }
    }
    current.points.push_back(sweep[k]);
  }
  if (current.points.size() > 1) passes.push_back(current);
  return passes;
}

/// The longest pass of a direction: the major branch.
const Pass* Major(const std::vector<Pass>& passes, bool rising) {
  const Pass* best = nullptr;
  double span = 0;
  for (const Pass& p : passes) {
    if (p.rising != rising) continue;
    const double s = std::fabs(p.points.back().drive_pa - p.points.front().drive_pa);
    if (s > span) {
      span = s;
      best = &p;
    }
  }
  return best;
}

/// Output against drive, sorted by drive and made non-decreasing (pool adjacent violators).
std::vector<SweepSample> Monotone(std::vector<SweepSample> points) {
  std::sort(points.begin(), points.end(),
            [](const SweepSample& a, const SweepSample& b) { return a.drive_pa < b.drive_pa; });
  std::vector<double> value, weight;
  std::vector<size_t> count;
  for (const SweepSample& p : points) {
    value.push_back(p.output);
    weight.push_back(1);
    count.push_back(1);
    while (value.size() > 1 && value[value.size() - 2] > value.back()) {
      const size_t n = value.size();
      const double w = weight[n - 2] + weight[n - 1];
      value[n - 2] = (value[n - 2] * weight[n - 2] + value[n - 1] * weight[n - 1]) / w;
      weight[n - 2] = w;
      count[n - 2] += count[n - 1];
      value.pop_back();
      weight.pop_back();
      count.pop_back();
    }
  }
  size_t at = 0;
  for (size_t b = 0; b < value.size(); ++b) {
    for (size_t i = 0; i < count[b]; ++i) points[at++].output = value[b];
  }
  return points;
}

/// The least drive at which a monotone curve reaches `level` (linear between points).
double DriveFor(const std::vector<SweepSample>& curve, double level) {
  if (level <= curve.front().output) return curve.front().drive_pa;
  for (size_t k = 1; k < curve.size(); ++k) {
    if (curve[k].output >= level) {
      const double span = curve[k].output - curve[k - 1].output;
      const double t = span > 0 ? (level - curve[k - 1].output) / span : 1.0;
      return curve[k - 1].drive_pa + t * (curve[k].drive_pa - curve[k - 1].drive_pa);
    }
  }
  return curve.back().drive_pa;
}

struct Branches {
  std::vector<double> levels, rising, falling;
  std::string error;
};

Branches ReadBranches(const std::vector<SweepSample>& sweep, int points) {
  Branches b;
  const auto passes = Passes(sweep);
  const Pass* up = Major(passes, true);
  const Pass* down = Major(passes, false);
  if (up == nullptr || down == nullptr || up->points.size() < 3 || down->points.size() < 3) {
    b.error = "sweep has no rising and falling major pass of 3 points or more";
    return b;
  }
  const auto rise = Monotone(up->points);
  const auto fall = Monotone(down->points);
  const double lo = std::max(rise.front().output, fall.front().output);
  const double hi = std::min(rise.back().output, fall.back().output);
  if (!(hi > lo)) {
    b.error = "rising and falling passes share no output range";
    return b;
  }
  for (int k = 0; k < points; ++k) {
    const double level = lo + (hi - lo) * k / (points - 1);
    b.levels.push_back(level);
    // Measured drives carry sensor noise: a reading just below 0 Pa is 0 Pa.
    double r = std::clamp(DriveFor(rise, level), 0.0, 100000.0);
    double f = std::clamp(DriveFor(fall, level), 0.0, 100000.0);
    if (k > 0) {  // strictly increasing, as the firmware requires
      r = std::max(r, b.rising.back() + 1.0);
      f = std::max(f, b.falling.back() + 1.0);
    }
    b.rising.push_back(r);
    b.falling.push_back(f);
  }
  return b;
}

std::vector<float> BranchParams(const Branches& b, double band, double dead_band) {
  const std::vector<float> y(b.levels.begin(), b.levels.end());
  const std::vector<float> up(b.rising.begin(), b.rising.end());
  const std::vector<float> down(b.falling.begin(), b.falling.end());
  const protocol::BranchParamSet set{static_cast<uint8_t>(y.size()),
                                     static_cast<float>(band),
                                     static_cast<float>(dead_band),
                                     y.data(),
                                     up.data(),
                                     down.data()};
  std::vector<float> p(protocol::BranchParamCount(set.points));
  protocol::WriteBranchParams(set, p.data(), p.size());
  return p;
}

/// Inverse residual of a branch compensator along the sweep: the drive it would have asked for
/// each measured output, against the drive that produced it.
void BranchResidual(const std::vector<float>& params, const std::vector<SweepSample>& sweep,
                    double* rms, double* worst) {
  protocol::ConfigureFinger f{};
  f.compensator = CompensatorKind::kBranch;
  f.param_count = static_cast<uint8_t>(params.size());
  std::copy(params.begin(), params.end(), f.params.begin());
  const core::Compensator c = core::MakeCompensator(f, 1e9f);
  core::CompensatorState s;
  core::HomeCompensator(c, s);
  double sum = 0;
  *worst = 0;
  for (size_t k = 1; k < sweep.size(); ++k) {
    const auto out = core::StepCompensator(c, s, static_cast<float>(sweep[k].output),
                                           static_cast<float>(sweep[k - 1].drive_pa));
    const double e = out.drive - sweep[k].drive_pa;
    sum += e * e;
    *worst = std::max(*worst, std::fabs(e));
  }
  *rms = std::sqrt(sum / static_cast<double>(sweep.size() - 1));
}

}  // namespace

HysteresisFit FitBranch(const std::vector<SweepSample>& sweep, int points) {
  HysteresisFit fit;
  fit.kind = CompensatorKind::kBranch;
  if (points < 2 || points > protocol::kMaxBranchPoints) {
    fit.error = "branch points must be 2..24";
    return fit;
  }
  fit.error = SweepError(sweep, static_cast<size_t>(2 * points), 1e6);
  if (!fit.ok()) return fit;
  const Branches b = ReadBranches(sweep, points);
  if (!b.error.empty()) {
    fit.error = b.error;
    return fit;
  }
  constexpr double kDeadBandPa = 500;  // above sensor noise, below a sweep step
  const double range = b.levels.back() - b.levels.front();
  double best = 1e300;
  for (double share : {0.02, 0.05, 0.1, 0.2, 0.4}) {
    const auto params = BranchParams(b, share * range, kDeadBandPa);
    double rms = 0, worst = 0;
    BranchResidual(params, sweep, &rms, &worst);
    if (rms < best) {
      best = rms;
      fit.params = params;
      fit.residual_rms = rms;
      fit.residual_max = worst;
    }
  }
  protocol::ConfigureFinger f{};
  if (const host::Outcome applied = ApplyFit(fit, f); !applied.ok()) fit.error = applied.message;
  return fit;
}

host::Result<std::vector<protocol::InversePoint>> FitStaticInverse(
    const std::vector<SweepSample>& sweep, int points, bool vacuum) {
  std::vector<protocol::InversePoint> inverse;
  if (points < 2 || points > protocol::kMaxInversePoints)
    return {host::Status::kInvalidArgument, "static inverse points must be 2..16"};
  const std::string bad = SweepError(sweep, static_cast<size_t>(2 * points), 1e6);
  const Branches b = bad.empty() ? ReadBranches(sweep, points) : Branches{{}, {}, {}, bad};
  if (!b.error.empty()) return {host::Status::kInvalidArgument, b.error};
  for (int k = 0; k < points; ++k) {
    protocol::InversePoint p;
    // Outputs are never negative (a reading just below 0 is the rig's noise at rest).
    p.output = static_cast<int32_t>(std::max(0L, std::lround(b.levels[static_cast<size_t>(k)])));
    const double drive =
        0.5 * (b.rising[static_cast<size_t>(k)] + b.falling[static_cast<size_t>(k)]);
    p.setpoint_pa = static_cast<int32_t>(std::lround(vacuum ? -drive : drive));
    if (!inverse.empty() && p.output <= inverse.back().output)
      continue;  // strictly increasing outputs
    inverse.push_back(p);
  }
  return inverse;
}

}  // namespace palpa::calibration
