// Each benchmark unit calibrated as palpa calibrate would on its rig: the regulator's static
// correction and the chamber's step response for the lines the steps run on, on an in-process
// rig of the same unit (the same regulator, sensor and actuator draws as the steps' board).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "palpa/calibration/chamber_step.h"
#include "palpa/calibration/procedures.h"
#include "palpa/host/chamber_tube.h"
#include "sim_rig.h"

namespace palpa::bench {

struct UnitCalibration {
  std::array<std::vector<protocol::CorrectionPoint>, protocol::kMaxLines> correction{};
  std::array<calibration::ChamberFit, protocol::kMaxLines> chamber{};
};

/// Calibrates `fingers` of `config` (by default fingers 0, pneumatic on line 0, and 3, jamming on
/// vacuum line 5, of thesis-5finger) on unit `seed`, once; each line a finger drives is indexed.
inline const UnitCalibration& CalibrationFor(uint32_t seed,
                                             const std::string& config = "thesis-5finger",
                                             const std::vector<uint8_t>& fingers = {0, 3}) {
  static std::map<std::pair<std::string, uint32_t>, UnitCalibration> known;
  const auto found = known.find({config, seed});
  if (found != known.end()) return found->second;
  UnitCalibration& u = known[{config, seed}];
  for (uint8_t finger : fingers) {
    testing::SimRig sim({config, finger, seed, seed});
    calibration::Rig rig = sim.rig();
    const uint8_t line = sim.driven_line(finger);
    calibration::RegulatorCorrection(rig, finger, line, 8, 3.0, &u.correction[line]);
    calibration::ContactOptions o;
    double zero = 0;
    calibration::ZeroOnVentedSurface(rig, finger, o, &zero);
    const calibration::ChamberStepOptions step = calibration::ChamberStepFor(sim.jamming(finger));
    calibration::ChamberStep measured;
    calibration::MeasureChamberStep(rig, finger, zero, o, step, &measured);
    u.chamber[line] = measured.fit;
  }
  return u;
}

/// The lag the board shapes a line with: the chamber's behind the outlet (the tube's law), as
/// the calibration file stores it; 0 (not shaped) where the calibration did not fit it — the lag
/// behind the regulator model means something else to the board.
inline double BoardLagS(const calibration::ChamberFit& f) { return f.ok ? f.outlet_tau_s : 0; }

/// A true step's start (its mean before the command) and end (its mean over the last 50 ms).
inline std::pair<double, double> StepEnds(const std::vector<std::pair<double, double>>& truth) {
  double start = 0, end = 0;
  int before = 0, tail = 0;
  for (const auto& [t, v] : truth) {
    if (t < 0) start += v, ++before;
    if (t > truth.back().first - 0.05) end += v, ++tail;
  }
  return {start / before, end / tail};
}

/// RMS of the normalised true chamber response of a step against what `fit` predicts for it.
inline double PredictionRms(const std::vector<std::pair<double, double>>& truth,
                            const calibration::ChamberFit& fit) {
  const auto [start, end] = StepEnds(truth);
  double sum = 0;
  int n = 0;
  for (const auto& [t, v] : truth) {
    if (t < 0) continue;
    const double e = (v - start) / (end - start) - calibration::ChamberResponse(fit, t);
    sum += e * e;
    ++n;
  }
  return std::sqrt(sum / n);
}

/// RMS, as PredictionRms, of the tube's law with lag `lag_s` at the board's reference run from a
/// step's true outlet pressure, as the board runs it, against its true chamber.
inline double TubePredictionRms(const std::vector<std::pair<double, double>>& truth,
                                const std::vector<std::pair<double, double>>& outlet,
                                protocol::LineKind kind, double lag_s) {
  const auto [start, end] = StepEnds(truth);
  const double k = host::TubeConstant(kind, lag_s);
  double c = truth.front().second, sum = 0;
  int n = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (truth[i].first >= 0) {
      const double e = (c - truth[i].second) / (end - start);
      sum += e * e, ++n;
    }
    if (i + 1 < truth.size())
      c = host::TubeChamberAfter(c, outlet[i].second, k, truth[i + 1].first - truth[i].first);
  }
  return std::sqrt(sum / n);
}

inline protocol::LineKind KindOf(bool jamming) {
  return jamming ? protocol::LineKind::kVacuum : protocol::LineKind::kPressure;
}

/// Mean RMS over `units` of each unit's own identified chamber (the lag behind the regulator
/// model, or with `tube` the tube's law behind the outlet) predicting its true step `from_kpa` →
/// `to_kpa` (magnitudes), a step other than the one it was identified with, `after_s` long.
inline double OtherStepRms(uint8_t finger, const std::vector<uint32_t>& units, double from_kpa,
                           double to_kpa, bool tube = false, double after_s = 0.6) {
  const uint8_t line = finger == 3 ? 5 : 0;
  double sum = 0;
  for (const uint32_t u : units) {
    std::vector<std::pair<double, double>> outlet;
    const auto truth = testing::TrueChamberStep({"thesis-5finger", finger, u, u}, from_kpa, to_kpa,
                                                &outlet, after_s);
    const calibration::ChamberFit& fit = CalibrationFor(u).chamber[line];
    sum += tube ? TubePredictionRms(truth, outlet, KindOf(finger == 3), fit.outlet_tau_s)
                : PredictionRms(truth, fit);
  }
  return sum / static_cast<double>(units.size());
}

/// The identification's figures per kind over `units`: the fitted lag (mean and range), the lag
/// a fit of the true chamber pressure gives, and the fit's error predicting the true step of
/// the same unit and of the next one; then, on `held_out` units that played no part in choosing
/// the identification step, each unit's own fit predicting its true steps of other sizes. Of the
/// lag behind the regulator model, or with `tube` of the model the board runs: the tube's lag at
/// the board's reference (ChamberFit::outlet_tau_s), the same law fitted to the true chamber
/// behind the true outlet, and the law run from each step's true outlet; its jamming line's deep
/// step held `deep_s` to settle.
inline std::string ChamberFitTable(const std::vector<uint32_t>& units,
                                   const std::vector<uint32_t>& held_out, bool tube = false,
                                   double deep_s = 0.6) {
  std::string t = std::string("| line | identification step | ") +
                  (tube ? "tube lag at the board's reference" : "chamber lag") +
                  " fitted from the force (ms): mean, range | from the true pressure (ms) | "
                  "prediction RMS, same unit | prediction RMS, next unit | held-out units, own "
                  "fit: 0 → 10 kPa | 10 → 30 kPa | 0 → 80 kPa |\n"
                  "|---|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (uint8_t finger : {0, 3}) {
    const bool jamming = finger == 3;
    const uint8_t line = jamming ? 5 : 0;
    const protocol::LineKind kind = KindOf(jamming);
    const calibration::ChamberStepOptions step = calibration::ChamberStepFor(jamming);
    double sum = 0, low = 1e9, high = 0, truth_sum = 0, same = 0, other = 0;
    for (size_t i = 0; i < units.size(); ++i) {
      const calibration::ChamberFit& fit = CalibrationFor(units[i]).chamber[line];
      const double lag = tube ? fit.outlet_tau_s : fit.tau_s;
      const uint32_t next = units[(i + 1) % units.size()];
      std::vector<std::pair<double, double>> outlet, next_outlet;
      const auto truth = testing::TrueChamberStep({"thesis-5finger", finger, units[i], units[i]},
                                                  step.from_kpa, step.to_kpa, &outlet);
      const auto next_truth = testing::TrueChamberStep({"thesis-5finger", finger, next, next},
                                                       step.from_kpa, step.to_kpa, &next_outlet);
      sum += lag;
      low = std::min(low, lag);
      high = std::max(high, lag);
      calibration::ChamberFit perfect;
      if (tube)
        calibration::FitTubeStep(truth, outlet, kind, &perfect);
      else
        perfect = calibration::FitChamberStep(truth, step.regulator_tau_s);
      truth_sum += tube ? perfect.outlet_tau_s : perfect.tau_s;
      same += tube ? TubePredictionRms(truth, outlet, kind, lag) : PredictionRms(truth, fit);
      other += tube ? TubePredictionRms(next_truth, next_outlet, kind, lag)
                    : PredictionRms(next_truth, fit);
    }
    const double n = static_cast<double>(units.size());
    // The bare line's deep vacuum steps outlast the 0.6 s window of a true step: not settled,
    // not normalisable; the tube's law is held longer for them.
    char deep[48] = "beyond the window";
    if (!jamming || tube)
      std::snprintf(deep, sizeof(deep), jamming ? "%.1f %% (held %.0f s)" : "%.1f %%",
                    100 * OtherStepRms(finger, held_out, 0, 80, tube, jamming ? deep_s : 0.6),
                    deep_s);
    char row[400];
    std::snprintf(row, sizeof(row),
                  "| %s | %.0f → %.0f kPa%s | %.1f (%.1f – %.1f) | %.1f | %.1f %% | %.1f %% | %.1f "
                  "%% | %.1f %% | %s |\n",
                  jamming ? "jamming vacuum" : "pneumatic", step.from_kpa, step.to_kpa,
                  jamming ? " of vacuum" : "", 1000 * sum / n, 1000 * low, 1000 * high,
                  1000 * truth_sum / n, 100 * same / n, 100 * other / n,
                  100 * OtherStepRms(finger, held_out, 0, 10, tube),
                  100 * OtherStepRms(finger, held_out, 10, 30, tube), deep);
    t += row;
  }
  return t;
}

}  // namespace palpa::bench
