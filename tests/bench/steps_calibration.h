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

/// RMS of the normalised true chamber response of a step against what `fit` predicts for it.
inline double PredictionRms(const std::vector<std::pair<double, double>>& truth,
                            const calibration::ChamberFit& fit) {
  double start = 0, end = 0, sum = 0;
  int before = 0, tail = 0, n = 0;
  for (const auto& [t, v] : truth) {
    if (t < 0) start += v, ++before;
    if (t > truth.back().first - 0.05) end += v, ++tail;
  }
  start /= before;
  end /= tail;
  for (const auto& [t, v] : truth) {
    if (t < 0) continue;
    const double e = (v - start) / (end - start) - calibration::ChamberResponse(fit, t);
    sum += e * e;
    ++n;
  }
  return std::sqrt(sum / n);
}

/// Mean RMS over `units` of each unit's own identified chamber predicting its true step
/// `from_kpa` → `to_kpa` (magnitudes), a step other than the one it was identified with.
inline double OtherStepRms(uint8_t finger, const std::vector<uint32_t>& units, double from_kpa,
                           double to_kpa) {
  const uint8_t line = finger == 3 ? 5 : 0;
  double sum = 0;
  for (const uint32_t u : units) {
    const auto truth = testing::TrueChamberStep({"thesis-5finger", finger, u, u}, from_kpa, to_kpa);
    sum += PredictionRms(truth, CalibrationFor(u).chamber[line]);
  }
  return sum / static_cast<double>(units.size());
}

/// The identification's figures per kind over `units`: the fitted lag (mean and range), the lag
/// a fit of the true chamber pressure gives, and the fit's error predicting the true step of
/// the same unit and of the next one; then, on `held_out` units that played no part in choosing
/// the identification step, each unit's own fit predicting its true steps of other sizes.
inline std::string ChamberFitTable(const std::vector<uint32_t>& units,
                                   const std::vector<uint32_t>& held_out) {
  std::string t =
      "| line | identification step | chamber lag fitted from the force (ms): mean, range | from "
      "the true pressure (ms) | prediction RMS, same unit | prediction RMS, next unit | held-out "
      "units, own fit: 0 → 10 kPa | 10 → 30 kPa | 0 → 80 kPa |\n"
      "|---|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (uint8_t finger : {0, 3}) {
    const bool jamming = finger == 3;
    const uint8_t line = jamming ? 5 : 0;
    const calibration::ChamberStepOptions step = calibration::ChamberStepFor(jamming);
    double sum = 0, low = 1e9, high = 0, truth_sum = 0, same = 0, other = 0;
    for (size_t i = 0; i < units.size(); ++i) {
      const calibration::ChamberFit& fit = CalibrationFor(units[i]).chamber[line];
      const uint32_t next = units[(i + 1) % units.size()];
      const auto truth = testing::TrueChamberStep({"thesis-5finger", finger, units[i], units[i]},
                                                  step.from_kpa, step.to_kpa);
      const auto next_truth = testing::TrueChamberStep({"thesis-5finger", finger, next, next},
                                                       step.from_kpa, step.to_kpa);
      sum += fit.tau_s;
      low = std::min(low, fit.tau_s);
      high = std::max(high, fit.tau_s);
      truth_sum += calibration::FitChamberStep(truth, step.regulator_tau_s).tau_s;
      same += PredictionRms(truth, fit);
      other += PredictionRms(next_truth, fit);
    }
    const double n = static_cast<double>(units.size());
    // The bare line's deep vacuum steps outlast the 0.6 s window of a true step: not settled,
    // not normalisable.
    char deep[32] = "beyond the window";
    if (!jamming)
      std::snprintf(deep, sizeof(deep), "%.1f %%", 100 * OtherStepRms(finger, held_out, 0, 80));
    char row[400];
    std::snprintf(row, sizeof(row),
                  "| %s | %.0f → %.0f kPa%s | %.1f (%.1f – %.1f) | %.1f | %.1f %% | %.1f %% | %.1f "
                  "%% | %.1f %% | %s |\n",
                  jamming ? "jamming vacuum" : "pneumatic", step.from_kpa, step.to_kpa,
                  jamming ? " of vacuum" : "", 1000 * sum / n, 1000 * low, 1000 * high,
                  1000 * truth_sum / n, 100 * same / n, 100 * other / n,
                  100 * OtherStepRms(finger, held_out, 0, 10),
                  100 * OtherStepRms(finger, held_out, 10, 30), deep);
    t += row;
  }
  return t;
}

}  // namespace palpa::bench
