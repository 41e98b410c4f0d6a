// PI and asymmetric-PI identification by non-negative least squares.
#include "palpa/calibration/hysteresis_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "palpa/calibration/nnls.h"
#include "palpa/core/compensator.h"
#include "palpa/protocol/compensator_params.h"

namespace palpa::calibration {
namespace {

using protocol::CompensatorKind;

std::vector<double> Drives(const std::vector<SweepSample>& s) {
  std::vector<double> u;
  for (const auto& p : s) u.push_back(p.drive_pa);
  return u;
}

std::vector<double> Outputs(const std::vector<SweepSample>& s) {
  std::vector<double> y;
  for (const auto& p : s) y.push_back(p.output);
  return y;
}

void Residuals(const std::vector<double>& fit, const std::vector<double>& y, HysteresisFit& out) {
  double sum = 0, worst = 0;
  for (size_t k = 0; k < y.size(); ++k) {
    const double e = fit[k] - y[k];
    sum += e * e;
    worst = std::max(worst, std::fabs(e));
  }
  out.residual_rms = std::sqrt(sum / static_cast<double>(y.size()));
  out.residual_max = worst;
}

/// w0 must stay strictly positive for the inverse: it is fitted as floor + a non-negative part.
constexpr double kW0FloorShare = 0.02;

/// PI weights on `target` (no intercept when `intercept` is null).
PlayModel FitPlay(const std::vector<double>& u, const std::vector<double>& target,
                  const std::vector<double>& r, double* intercept) {
  const auto z = PlayOutputs(u, r);
  const double u_max = *std::max_element(u.begin(), u.end());
  const double t_range = *std::max_element(target.begin(), target.end()) -
                         *std::min_element(target.begin(), target.end());
  const double w0_floor = kW0FloorShare * (u_max > 0 ? t_range / u_max : 0);
  Matrix a;
  std::vector<double> b;
  for (size_t k = 0; k < u.size(); ++k) {
    std::vector<double> row{u[k]};
    row.insert(row.end(), z[k].begin(), z[k].end());
    a.push_back(row);
    b.push_back(target[k] - w0_floor * u[k]);
  }
  double c = 0;
  const NnlsResult x = intercept != nullptr ? SolveNnlsWithIntercept(a, b, &c) : SolveNnls(a, b);
  PlayModel m;
  m.offset = c;
  m.w0 = w0_floor + x.x[0];
  m.thresholds = r;
  m.weights.assign(x.x.begin() + 1, x.x.end());
  if (intercept != nullptr) *intercept = c;
  return m;
}

/// Asymmetric PI by equation error (Kuhnen's modified PI): S⁻¹ is itself a superposition of
/// dead zones, so y + Σ h_k·max(y − e_k, 0) = w0·u + Σ w_i·z_i + c is linear in every unknown.
/// The h_k take either sign (two non-negative columns each); S⁻¹'s slopes must stay positive.
PlayModel FitAsymmetric(const std::vector<double>& u, const std::vector<double>& y,
                        const std::vector<double>& r, int dead_zones) {
  std::vector<double> sorted = y;
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> e;
  for (int k = 1; k <= dead_zones; ++k) {
    const double q =
        sorted[sorted.size() * static_cast<size_t>(k) / static_cast<size_t>(dead_zones + 1)];
    if (e.empty() || q > e.back() + 1e-9 * (1 + std::fabs(q))) e.push_back(q);
  }
  const auto z = PlayOutputs(u, r);
  const double u_max = *std::max_element(u.begin(), u.end());
  const double w0_floor =
      kW0FloorShare * (u_max > 0 ? (sorted.back() - sorted.front()) / u_max : 0);
  Matrix a;
  std::vector<double> b;
  for (size_t k = 0; k < u.size(); ++k) {
    std::vector<double> row{u[k]};
    row.insert(row.end(), z[k].begin(), z[k].end());
    for (double knot : e) {
      const double hinge = std::max(y[k] - knot, 0.0);
      row.push_back(-hinge);  // h_k > 0
      row.push_back(hinge);   // h_k < 0
    }
    a.push_back(row);
    b.push_back(y[k] - w0_floor * u[k]);
  }
  double c = 0;
  const NnlsResult x = SolveNnlsWithIntercept(a, b, &c);
  PlayModel m;
  m.offset = c;
  m.w0 = w0_floor + x.x[0];
  m.thresholds = r;
  m.weights.assign(x.x.begin() + 1, x.x.begin() + 1 + static_cast<long>(r.size()));
  // S⁻¹ in y' = y − c: knots e_k − c (kept where ≥ 0), slopes 1 + Σ h. Forward S: knots at
  // S⁻¹(e_k − c), slopes the reciprocals.
  constexpr double kSlopeFloor = 0.05;
  double inverse_slope = 1, v_knot = 0, y_knot = 0, forward_slope = 1;
  for (size_t k = 0; k < e.size(); ++k) {
    const double h = x.x[1 + r.size() + 2 * k] - x.x[2 + r.size() + 2 * k];
    const double knot = e[k] - c;
    if (knot <= y_knot) continue;
    v_knot += (knot - y_knot) * inverse_slope;
    y_knot = knot;
    inverse_slope = std::max(inverse_slope + h, kSlopeFloor);
    const double slope = 1.0 / inverse_slope;
    m.dead_zones.push_back(v_knot);
    m.gains.push_back(slope - forward_slope);
    forward_slope = slope;
  }
  return m;
}

std::vector<float> PlayParams(CompensatorKind kind, const PlayModel& m) {
  auto floats = [](const std::vector<double>& v) { return std::vector<float>(v.begin(), v.end()); };
  const std::vector<float> r = floats(m.thresholds), w = floats(m.weights);
  const std::vector<float> d = floats(m.dead_zones), g = floats(m.gains);
  protocol::PlayParamSet set;
  set.operators = static_cast<uint8_t>(r.size());
  set.dead_zones = static_cast<uint8_t>(d.size());
  set.offset = static_cast<float>(m.offset);
  set.w0 = static_cast<float>(m.w0);
  set.thresholds = r.data();
  set.weights = w.data();
  set.dead_zone_thresholds = d.data();
  set.dead_zone_gains = g.data();
  std::vector<float> p(protocol::PlayParamCount(kind, set.operators, set.dead_zones));
  protocol::WritePlayParams(kind, set, p.data(), p.size());
  return p;
}

/// Readings a play-model fit needs: about two per unknown (w0, offset, and per operator and per
/// dead zone one each; an api dead zone's slope takes two non-negative columns).
size_t PlayFitPoints(int operators, int dead_zones) {
  return static_cast<size_t>(2 * operators + 2 * dead_zones + 4);
}

/// The model's operators, and those with a weight.
void CountOperators(const PlayModel& m, HysteresisFit& fit) {
  fit.operators = static_cast<int>(m.weights.size());
  fit.operators_used =
      static_cast<int>(std::count_if(m.weights.begin(), m.weights.end(), [](double w) {
        return static_cast<float>(w) != 0.0f;  // as the board gets it
      }));
}

/// Refuses parameter sets the firmware would refuse, with its reason.
void CheckWithFirmware(HysteresisFit& fit) {
  protocol::ConfigureFinger f{};
  if (const host::Outcome applied = ApplyFit(fit, f); !applied.ok()) fit.error = applied.message;
}

}  // namespace

size_t MinSweepPoints(CompensatorKind kind, int operators) {
  switch (kind) {
    case CompensatorKind::kPrandtlIshlinskii:
      return PlayFitPoints(operators, 0);
    case CompensatorKind::kAsymmetricPi:
      return PlayFitPoints(operators, kApiDeadZones);
    default:
      return 0;
  }
}

int MaxOperators(CompensatorKind kind, size_t points) {
  int n = 0;
  while (n < core::kMaxPlayOperators && MinSweepPoints(kind, n + 1) <= points) ++n;
  return n;
}

std::string SweepError(const std::vector<SweepSample>& sweep, size_t min_points, double drive_max) {
  if (sweep.size() < min_points) {
    return "sweep has " + std::to_string(sweep.size()) + " points; this fit needs at least " +
           std::to_string(min_points);
  }
  for (size_t k = 0; k < sweep.size(); ++k) {
    const SweepSample& s = sweep[k];
    if (!std::isfinite(s.drive_pa) || !std::isfinite(s.output))
      return "sweep point " + std::to_string(k) + " is not finite";
    if (s.drive_pa < -0.02 * drive_max || s.drive_pa > 1.02 * drive_max) {
      return "sweep point " + std::to_string(k) + ": drive " + std::to_string(s.drive_pa) +
             " Pa outside 0.." + std::to_string(drive_max);
    }
  }
  return {};
}

HysteresisFit FitPi(const std::vector<SweepSample>& sweep, int operators, double drive_max) {
  HysteresisFit fit;
  fit.kind = CompensatorKind::kPrandtlIshlinskii;
  if (operators < 1 || operators > protocol::kMaxPlayOperators) {
    fit.error = "operator count must be 1..32";
    return fit;
  }
  fit.error = SweepError(sweep, MinSweepPoints(fit.kind, operators), drive_max);
  if (!fit.ok()) return fit;
  std::vector<double> u = Drives(sweep);
  for (double& x : u) x = std::max(x, 0.0);
  const std::vector<double> y = Outputs(sweep);
  double c = 0;
  const PlayModel m = FitPlay(u, y, EvenThresholds(operators, drive_max), &c);
  Residuals(m.Simulate(u), y, fit);
  CountOperators(m, fit);
  fit.params = PlayParams(fit.kind, m);
  CheckWithFirmware(fit);
  return fit;
}

HysteresisFit FitApi(const std::vector<SweepSample>& sweep, int operators, int dead_zones,
                     double drive_max) {
  HysteresisFit fit;
  fit.kind = CompensatorKind::kAsymmetricPi;
  if (operators < 1 || dead_zones < 1 || dead_zones > protocol::kMaxDeadZones ||
      protocol::PlayParamCount(CompensatorKind::kAsymmetricPi, static_cast<size_t>(operators),
                               static_cast<size_t>(dead_zones)) > protocol::kMaxCompensatorParams) {
    fit.error = "api needs 1..32 operators and 1..8 dead zones within 80 parameters";
    return fit;
  }
  fit.error = SweepError(sweep, PlayFitPoints(operators, dead_zones), drive_max);
  if (!fit.ok()) return fit;
  std::vector<double> u = Drives(sweep);
  for (double& x : u) x = std::max(x, 0.0);
  const std::vector<double> y = Outputs(sweep);
  const PlayModel best = FitAsymmetric(u, y, EvenThresholds(operators, drive_max), dead_zones);
  if (best.dead_zones.empty()) {
    fit.error = "no dead-zone knot above the offset: the loop needs no api (fit pi)";
    return fit;
  }
  Residuals(best.Simulate(u), y, fit);
  CountOperators(best, fit);
  fit.params = PlayParams(fit.kind, best);
  CheckWithFirmware(fit);
  return fit;
}

HysteresisFit FitCompensator(CompensatorKind kind, int size, const std::vector<SweepSample>& sweep,
                             double drive_max) {
  switch (kind) {
    case CompensatorKind::kBranch:
      return FitBranch(sweep, size);
    case CompensatorKind::kPrandtlIshlinskii:
      return FitPi(sweep, size, drive_max);
    case CompensatorKind::kAsymmetricPi:
      return FitApi(sweep, size, kApiDeadZones, drive_max);
    default:
      return HysteresisFit{};  // none: the static inverse alone
  }
}

HysteresisFit FitBetterPlayModel(const std::vector<SweepSample>& sweep, int operators,
                                 double drive_max, std::string* comparison) {
  HysteresisFit pi = FitPi(sweep, operators, drive_max);
  HysteresisFit api = FitApi(sweep, operators, kApiDeadZones, drive_max);
  const std::string n = "(" + std::to_string(operators) + ")";
  char text[160];
  if (!api.ok()) {
    std::snprintf(text, sizeof(text), "pi%s; api%s not fitted: %s", n.c_str(), n.c_str(),
                  api.error.c_str());
    *comparison = text;
    return pi;
  }
  if (!pi.ok()) {
    *comparison = "api" + n + "; pi" + n + " not fitted: " + pi.error;
    return api;
  }
  const bool api_better = api.residual_rms <= 0.75 * pi.residual_rms;
  std::snprintf(text, sizeof(text), "%s: api%s %.3g against pi%s %.3g RMS",
                api_better ? "api" : "pi", n.c_str(), api.residual_rms, n.c_str(), pi.residual_rms);
  *comparison = text;
  return api_better ? api : pi;
}

PlayModel ModelOf(CompensatorKind kind, const std::vector<float>& params) {
  PlayModel m;
  protocol::PlayParamSet set;
  if (protocol::ReadPlayParams(kind, params.data(), params.size(), set) != nullptr) return m;
  m.offset = set.offset;
  m.w0 = set.w0;
  m.thresholds.assign(set.thresholds, set.thresholds + set.operators);
  m.weights.assign(set.weights, set.weights + set.operators);
  m.dead_zones.assign(set.dead_zone_thresholds, set.dead_zone_thresholds + set.dead_zones);
  m.gains.assign(set.dead_zone_gains, set.dead_zone_gains + set.dead_zones);
  return m;
}

host::Outcome ApplyFit(const HysteresisFit& fit, protocol::ConfigureFinger& finger) {
  if (fit.params.size() > protocol::kMaxCompensatorParams)
    return host::Outcome::Fail(host::Status::kBadValue, "more than 80 compensator parameters");
  protocol::ConfigureFinger candidate = finger;
  candidate.compensator = fit.kind;
  candidate.param_count = static_cast<uint8_t>(fit.params.size());
  std::copy(fit.params.begin(), fit.params.end(), candidate.params.begin());
  if (const char* why = core::CompensatorParamsError(candidate)) {
    return host::Outcome::Fail(host::Status::kBadValue,
                               std::string("the firmware would refuse these parameters: ") + why);
  }
  finger = candidate;
  return {};
}

}  // namespace palpa::calibration
