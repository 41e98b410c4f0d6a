// The five failure detectors of a calibration run.
#include "palpa/calibration/quality_checks.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "procedure_support.h"

namespace palpa::calibration {
namespace {

using host::QualityCheck;

QualityCheck Check(const char* name, double value, double limit, bool passed, std::string detail) {
  return QualityCheck{name, value, limit, passed, std::move(detail)};
}

QualityCheck Points(const CheckInputs& in) {
  if (in.jamming) {
    std::set<std::pair<double, double>> conditions;
    std::set<double> biases, vacuums;
    int short_presses = 0;
    for (const MapPress& p : in.map) {
      conditions.insert({p.bias_kpa, p.vacuum_kpa});
      biases.insert(p.bias_kpa);
      vacuums.insert(p.vacuum_kpa);
      if (p.readings < kMinPressReadings) ++short_presses;
    }
    const int n = static_cast<int>(conditions.size());
    const bool spans = biases.size() >= 2 && vacuums.size() >= 3;
    const bool ok =
        n >= kMinMapConditions && spans && short_presses == 0 && in.sweep_points >= kMinSweepPoints;
    std::string detail = std::to_string(n) + " map conditions (" + std::to_string(biases.size()) +
                         " biases × " + std::to_string(vacuums.size()) + " vacuums; at least " +
                         std::to_string(kMinMapConditions) + " over 2 × 3 wanted), " +
                         std::to_string(in.sweep_points) + " sweep readings (at least " +
                         std::to_string(kMinSweepPoints) + ")";
    if (short_presses > 0) {
      detail += ", " + std::to_string(short_presses) + " presses with fewer than " +
                std::to_string(kMinPressReadings) + " readings";
    }
    return Check("points", n, kMinMapConditions, ok, detail);
  }
  return Check("points", in.sweep_points, kMinSweepPoints, in.sweep_points >= kMinSweepPoints,
               std::to_string(in.sweep_points) + " sweep readings (at least " +
                   std::to_string(kMinSweepPoints) + ")");
}

QualityCheck Noise(const CheckInputs& in) {
  std::vector<double> residuals;
  for (const MapPress& p : in.map) residuals.push_back(p.residual_n);
  double press = 0;
  if (!residuals.empty()) {
    std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
    press = residuals[residuals.size() / 2];
  }
  // The press fit's residual also carries its own misfit and the jitter between a position and a
  // force reading taken a moment apart: it is held to twice the limit the sensor alone is.
  // In mN, the calibration file's unit of force (CheckUnit).
  const double value = 1000 * std::max(in.tare_noise_n, press / 2);
  const double limit = 1000 * kNoiseLimitClasses * in.force_noise_class_n;
  std::string detail = "force noise " + Num(in.tare_noise_n * 1000) + " mN RMS clear of the finger";
  if (!residuals.empty()) detail += ", " + Num(press * 1000) + " mN median press-fit residual";
  detail += "; the sensor's class is " + Num(in.force_noise_class_n * 1000) + " mN";
  return Check("noise", value, limit, value <= limit, detail);
}

QualityCheck Leak(const CheckInputs& in) {
  double worst = 0;
  std::string detail = "every line holds its commands within the regulator's class";
  // Trim off (the regulator correction): the line's own static error, against its data sheet.
  for (const host::RegulatorCorrection& c : in.corrections) {
    for (const protocol::CorrectionPoint& p : c.points) {
      const double command = std::fabs(p.command_pa / 1000.0);
      const double held = std::fabs(0.5 * (p.rising_pa + p.falling_pa) / 1000.0);
      const double ratio = (command - held) / in.regulator.AllowedDeficitKpa(command);
      if (ratio > worst) {
        worst = ratio;
        detail = "line " + std::to_string(c.line + 1) + " holds " + Num(held) + " kPa at a " +
                 Num(command) + " kPa command with its trim off (its class allows " +
                 Num(in.regulator.AllowedDeficitKpa(command), 2) + " kPa short)";
      }
    }
  }
  // Trim on (every map condition): the loop must have brought the line to its setpoint. Only up
  // to where the correction went (90 % of the line's range): above it a regulator whose gain is
  // low inside its class needs a command beyond the line's limit, leak or none.
  double top_pressure = 0.9 * in.regulator.full_scale_kpa, top_vacuum = top_pressure;
  if (!in.corrections.empty()) top_pressure = top_vacuum = 0;
  for (const host::RegulatorCorrection& c : in.corrections) {
    for (const protocol::CorrectionPoint& p : c.points) {
      double& top = p.command_pa < 0 ? top_vacuum : top_pressure;
      top = std::max(top, std::fabs(p.command_pa / 1000.0));
    }
  }
  for (const MapPress& p : in.map) {
    const double pairs[2][2] = {{p.bias_kpa, p.measured_bias_kpa},
                                {p.vacuum_kpa, p.measured_vacuum_kpa}};
    for (const auto& [command, measured] : pairs) {
      const double top = command < 0 ? top_vacuum : top_pressure;
      if (std::fabs(command) < 1 || std::fabs(command) > top + 1e-6) continue;  // vented, or above
      const double ratio = (std::fabs(command) - std::fabs(measured)) / kHeldToleranceKpa;
      if (ratio > worst) {
        worst = ratio;
        detail = "a line reads " + Num(measured) + " kPa at a " + Num(command) +
                 " kPa setpoint with its trim on";
      }
    }
  }
  return Check("leak", worst, 1, worst <= 1, detail);
}

/// The relative spread a pneumatic calibration claims for itself (fit residual over its span).
double CurveSpread(const host::CalibrationFile& f) {
  double range = 0;
  if (f.curve.size() >= 2) range = std::fabs(f.curve.back().output - f.curve.front().output);
  return range > 0 ? std::max(f.quality.residual_rms / range, kSpreadFloor) : kSpreadFloor;
}

std::optional<QualityCheck> Previous(const CheckInputs& in, const host::CalibrationFile& fresh) {
  const host::CalibrationFile* old = in.previous;
  if (old == nullptr || old->kind != fresh.kind) return std::nullopt;
  // Each point is held to its own allowance: kPreviousLimitSigmas × the two spreads there.
  double worst_ratio = 0, worst = 0, allowed = 0;
  std::string where;
  auto consider = [&](double difference, double spread, const std::string& at) {
    const double limit = kPreviousLimitSigmas * spread;
    if (std::fabs(difference) / limit > worst_ratio) {
      worst_ratio = std::fabs(difference) / limit;
      worst = difference;
      allowed = limit;
      where = at;
    }
  };
  if (in.jamming && !old->grid.empty() && !in.map.empty()) {
    // The old map's conditions, where it measured: its spread there against the new surface's
    // own uncertainty there (small where the new run pressed nearby).
    // Where the new run pressed the same condition its own presses answer; elsewhere its surface.
    // The old file's grid is in Pa and mN/mm, the rig's map in kPa and N/mm.
    const StiffnessSurface now(StiffnessSamples(in.map), in.box);
    const std::vector<ConditionSummary> pressed = SummariseConditions(in.map);
    for (const host::GridPoint& g : old->grid) {
      const double bias = g.bias_pa / 1000, vacuum = g.vacuum_pa / 1000;
      const double mean = g.stiffness_mean / 1000, spread = g.stiffness_spread / 1000;
      MapPrediction p = now.Predict(bias, vacuum);
      for (const ConditionSummary& q : pressed) {
        if (FileGridPoint(q).bias_pa == g.bias_pa && FileGridPoint(q).vacuum_pa == g.vacuum_pa) {
          p = {q.stiffness_mean, q.stiffness_spread};
        }
      }
      const double old_spread = std::max(spread / mean, kSpreadFloor);
      const double new_spread = std::max(p.sd / p.mean, kSpreadFloor);
      consider((p.mean - mean) / mean, std::hypot(old_spread, new_spread),
               "bias " + Num(bias) + " kPa, vacuum " + Num(vacuum) + " kPa");
    }
  } else if (old->curve.size() >= 2 && fresh.curve.size() >= 2) {
    // Output curves over their common drive range, relative to the old curve's span.
    const double span = std::fabs(old->curve.back().output - old->curve.front().output);
    const double spread = std::hypot(CurveSpread(*old), CurveSpread(fresh));
    for (const host::CurvePoint& q : old->curve) {
      for (size_t i = 1; i < fresh.curve.size(); ++i) {
        const host::CurvePoint &a = fresh.curve[i - 1], &b = fresh.curve[i];
        if (q.drive_pa < std::min(a.drive_pa, b.drive_pa) ||
            q.drive_pa > std::max(a.drive_pa, b.drive_pa))
          continue;
        const double t = (q.drive_pa - a.drive_pa) / (b.drive_pa - a.drive_pa);
        consider((a.output + t * (b.output - a.output) - q.output) / span, spread,
                 Num(q.drive_pa / 1000) + " kPa");
        break;
      }
    }
  } else {
    return std::nullopt;
  }
  if (where.empty()) return std::nullopt;
  return Check("previous", worst_ratio, 1, worst_ratio <= 1,
               "differs from the calibration of " + old->date + " by " + Num(100 * worst, 2) +
                   " % at " + where + " (the two spreads allow " + Num(100 * allowed, 2) +
                   " % there)");
}

}  // namespace

QualityCheck CheckForceZero(const CheckInputs& in) {
  double worst = 0;
  for (const MapPress& p : in.map) worst = std::max(worst, std::fabs(p.free_force_n));
  for (double f : in.free_readings) worst = std::max(worst, std::fabs(f));
  const double worst_mn = 1000 * worst,
               limit_mn = 1000 * kZeroLimitClasses * in.force_noise_class_n;
  return Check("force_zero", worst_mn, limit_mn, worst_mn <= limit_mn,
               "readings clear of the finger stray up to " + Num(worst_mn) +
                   " mN from the tare (limit " + Num(limit_mn) + " mN)");
}

double RegulatorClass::AllowedDeficitKpa(double command_kpa) const {
  return gain * command_kpa + (linearity_fs + repeatability_fs) * full_scale_kpa +
         sensor_fss * sensor_span_kpa;
}

std::vector<QualityCheck> RunQualityChecks(const CheckInputs& in,
                                           const host::CalibrationFile& fresh) {
  std::vector<QualityCheck> out = {Points(in), Noise(in), CheckForceZero(in), Leak(in)};
  if (auto p = Previous(in, fresh)) out.push_back(*p);
  return out;
}

}  // namespace palpa::calibration
