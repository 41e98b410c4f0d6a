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

/// The identification's figures per kind over `units`: the fitted lag (mean and range), the lag
/// a fit of the true chamber pressure gives, and the fit's error predicting the true step of
/// the same unit and of the next one (held out).
inline std::string ChamberFitTable(const std::vector<uint32_t>& units) {
  std::string t =
      "| line | identification step | chamber lag fitted from the force (ms): mean, range | from "
      "the true pressure (ms) | prediction RMS, same unit | prediction RMS, held-out unit |\n"
      "|---|---|---|---:|---:|---:|\n";
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
      const auto held_out = testing::TrueChamberStep({"thesis-5finger", finger, next, next},
                                                     step.from_kpa, step.to_kpa);
      sum += fit.tau_s;
      low = std::min(low, fit.tau_s);
      high = std::max(high, fit.tau_s);
      truth_sum += calibration::FitChamberStep(truth, step.regulator_tau_s).tau_s;
      same += PredictionRms(truth, fit);
      other += PredictionRms(held_out, fit);
    }
    const double n = static_cast<double>(units.size());
    char row[320];
    std::snprintf(row, sizeof(row),
                  "| %s | %.0f → %.0f kPa%s | %.1f (%.1f – %.1f) | %.1f | %.1f %% | %.1f %% |\n",
                  jamming ? "jamming vacuum" : "pneumatic", step.from_kpa, step.to_kpa,
                  jamming ? " of vacuum" : "", 1000 * sum / n, 1000 * low, 1000 * high,
                  1000 * truth_sum / n, 100 * same / n, 100 * other / n);
    t += row;
  }
  return t;
}

}  // namespace palpa::bench
