// Where a deep jamming step spends its time: 0 → −80 kPa of vacuum on held-out units (plant level
// 3, 20 kPa bias), shaped with the chamber lag the calibration identified (at 5 → 20 kPa of
// vacuum) and with that lag scaled, against the plant's own fastest step. Prints Markdown.
//   palpa_deep_step_bench
#include <algorithm>
#include <cmath>
#include <cstdio>

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
    if (!u.chamber[c.line].ok || scale <= 0) return;
    const float lag_s = (c.line == kVacuum ? scale : 1.0f) * u.chamber[c.line].tau_s;
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
    const double identified_ms = 1000.0 * pb::CalibrationFor(seed).chamber[kVacuum].tau_s;
    for (float scale : {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 6.0f}) {
      const DeepStep d = Run(seed, scale);
      char lag[64];
      if (scale == 0)
        std::snprintf(lag, sizeof(lag), "not shaped");
      else
        std::snprintf(lag, sizeof(lag), "%.0f (identified × %.0f)", scale * identified_ms, scale);
      char settled[32];
      std::snprintf(settled, sizeof(settled), "%.0f", d.settle_ms);
      std::printf("| %u | %s | %d | %.1f | %s | %.2f |\n", seed, lag, d.overdrive_ends_ms,
                  d.chamber_at_100ms / 1000, d.settle_ms == pb::kNever ? "never" : settled,
                  d.overshoot_pa / 1000);
    }
  }
  return 0;
}
