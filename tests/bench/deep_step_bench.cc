// Where a deep jamming step spends its time: 0 → −80 kPa of vacuum on held-out units (plant level
// 3, 20 kPa bias), shaped with the chamber lag the calibration identified (at 5 → 20 kPa of
// vacuum) and with that lag scaled, against the plant's own fastest step; then the lag the same
// step measurement fits at increasing depth (what a chamber model that follows the pressure would
// be identified from). Prints Markdown.
//   palpa_deep_step_bench
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "palpa/host/chamber_tube.h"
#include "steps_calibration.h"
#include "steps_measure.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;

namespace {

constexpr uint8_t kBias = 3, kVacuum = 5;
constexpr double kTarget = -80000;

struct DeepStep {
  int overdrive_ends_ms = 0;
  double chamber_at_100ms = 0, settle_ms = pb::kNever, overshoot_pa = 0;
};

/// One 0 → −80 kPa step on `seed`'s unit, calibrated, the vacuum line shaped with its identified
/// chamber lag × `scale` (0: not shaped); the true chamber pressure read every millisecond.
DeepStep Run(uint32_t seed, float scale) {
  const pb::UnitCalibration& u = pb::CalibrationFor(seed);
  palpa::sim::PlantOptions plant;
  plant.level = 3;
  plant.seed = plant.unit = seed;
  pb::RawLineSession s(plant, [&u, scale](pp::ConfigureLine& c) {
    c.slew_pa_per_s = 0;
    const auto& correction = u.correction[c.line];
    c.correction_count = static_cast<uint8_t>(correction.size());
    std::copy(correction.begin(), correction.end(), c.correction.begin());
    if (pb::BoardLagS(u.chamber[c.line]) <= 0 || scale <= 0) return;
    const float lag_s =
        (c.line == kVacuum ? scale : 1.0f) * static_cast<float>(pb::BoardLagS(u.chamber[c.line]));
    c.chamber_tau_us = static_cast<uint32_t>(lag_s * 1e6f);
    c.overdrive_pa = 20000;
  });
  s.Set({{kBias, 20000}});
  for (int ms = 0; ms < 2500; ++ms) s.Tick();
  s.Set({{kVacuum, static_cast<int32_t>(kTarget)}});
  DeepStep d;
  const double band = pb::Band(0, kTarget);
  constexpr int kDwellMs = 1500;
  int last_outside = 0;
  for (int ms = 1; ms <= kDwellMs; ++ms) {
    s.Tick();
    const double chamber = s.Chamber(kVacuum);
    if (s.Status(kVacuum) & pp::line_status::kShaping) d.overdrive_ends_ms = ms;
    if (ms == 100) d.chamber_at_100ms = chamber;
    if (std::fabs(chamber - kTarget) > band) last_outside = ms;
    d.overshoot_pa = std::max(d.overshoot_pa, kTarget - chamber);
  }
  d.settle_ms = last_outside >= kDwellMs ? pb::kNever : last_outside;
  return d;
}

/// The chamber lag the calibration's step measurement fits on `seed`'s jamming finger for a step
/// of `from_kpa` → `to_kpa` of vacuum (the identification's procedure, a longer window).
palpa::calibration::ChamberFit LagAt(uint32_t seed, double from_kpa, double to_kpa) {
  constexpr uint8_t kJamming = 3;
  palpa::testing::SimRig sim({"thesis-5finger", kJamming, seed, seed});
  palpa::calibration::Rig rig = sim.rig();
  palpa::calibration::ContactOptions o;
  double zero = 0;
  palpa::calibration::ZeroOnVentedSurface(rig, kJamming, o, &zero);
  palpa::calibration::ChamberStepOptions step = palpa::calibration::ChamberStepFor(true);
  step.from_kpa = from_kpa;
  step.to_kpa = to_kpa;
  step.after_s = 1.2;
  palpa::calibration::ChamberStep measured;
  palpa::calibration::MeasureChamberStep(rig, kJamming, zero, o, step, &measured);
  return measured.fit;
}

/// Lags fitted at increasing depth against the tube's mean absolute pressure over the step: a
/// laminar tube's conductance is proportional to it, so lag × pressure stays put if the tube is
/// what slows the chamber.
void LagsByDepth() {
  std::printf(
      "\nThe chamber lag fitted at depth (the calibration's step measurement, 1.2 s window):\n\n"
      "| unit | step (kPa of vacuum) | mean absolute pressure (kPa) | lag (ms) | × the 5 → 20 "
      "lag | lag × pressure (ms·kPa) | fit RMS | lag behind the outlet (ms) | × pressure (ms·kPa) "
      "| "
      "its fit RMS |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  constexpr double kAtmKpa = 101.325;
  for (uint32_t seed : {101u, 102u, 103u}) {
    double shallow = 0;
    for (const auto& [from, to] : {std::pair{5.0, 20.0}, std::pair{20.0, 40.0},
                                   std::pair{40.0, 60.0}, std::pair{60.0, 80.0}}) {
      const palpa::calibration::ChamberFit fit = LagAt(seed, from, to);
      if (!fit.ok) {
        std::printf("| %u | %.0f → %.0f | no fit | | | | |\n", seed, from, to);
        continue;
      }
      const double mean_abs = kAtmKpa - (from + to) / 2;
      if (shallow == 0) shallow = fit.tau_s;
      // The fit stores the tube's lag at the board's reference; here, at the step's own mean.
      const double k = palpa::host::TubeConstant(pp::LineKind::kVacuum, fit.outlet_tau_s);
      const double outlet_lag_s = 1 / (2 * k * 1e3 * mean_abs);
      std::printf(
          "| %u | %.0f → %.0f | %.1f | %.1f | %.2f | %.0f | %.1f %% | %.1f | %.0f | %.1f %% |\n",
          seed, from, to, mean_abs, 1e3 * fit.tau_s, fit.tau_s / shallow,
          1e3 * fit.tau_s * mean_abs, 100 * fit.rms, 1e3 * outlet_lag_s,
          1e3 * outlet_lag_s * mean_abs, 100 * fit.outlet_rms);
    }
  }
}

}  // namespace

int main() {
  const double fastest = pb::FastestMs(pp::LineKind::kVacuum, 0, kTarget);
  std::printf(
      "0 → −80 kPa on the jamming vacuum line (20 kPa bias); the plant's fastest %.0f ms, "
      "goal %.0f ms\n\n",
      fastest, pb::GoalMs(fastest));
  std::printf(
      "| unit | chamber lag (ms) | overdrive ends (ms) | chamber at 100 ms (kPa) | settled "
      "(ms) | overshoot (kPa) |\n|---|---|---:|---:|---:|---:|\n");
  for (uint32_t seed : {101u, 102u, 103u}) {
    const double identified_ms = 1000.0 * pb::BoardLagS(pb::CalibrationFor(seed).chamber[kVacuum]);
    for (float scale : {0.0f, 0.8f, 0.9f, 1.0f, 1.1f, 1.25f, 1.5f, 2.0f, 4.0f}) {
      const DeepStep d = Run(seed, scale);
      char lag[64];
      if (scale == 0)
        std::snprintf(lag, sizeof(lag), "not shaped");
      else
        std::snprintf(lag, sizeof(lag), "%.0f (identified × %.2g)", scale * identified_ms, scale);
      char settled[32];
      std::snprintf(settled, sizeof(settled), "%.0f", d.settle_ms);
      std::printf("| %u | %s | %d | %.1f | %s | %.2f |\n", seed, lag, d.overdrive_ends_ms,
                  d.chamber_at_100ms / 1000, d.settle_ms == pb::kNever ? "never" : settled,
                  d.overshoot_pa / 1000);
    }
  }
  LagsByDepth();
  return 0;
}
