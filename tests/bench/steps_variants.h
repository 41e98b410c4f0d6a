// What the step benchmark compares: the lines it steps and the ways of driving them (feed-forward
// alone, with the trim), and the settling-against-overshoot charts it draws from them.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"
#include "raw_line_session.h"
#include "steps_calibration.h"

namespace palpa::bench {

/// A line the steps run on; a vacuum line's bias line is held at 20 kPa first.
struct LineUnderTest {
  const char* name;
  uint8_t line;
  protocol::LineKind kind;
  double sign;
  void Hold(RawLineSession& s) const {
    if (kind != protocol::LineKind::kVacuum) return;
    s.Set({{3, 20000}});
    for (int ms = 0; ms < 1000; ++ms) s.Tick();
  }
};

inline std::vector<LineUnderTest> Lines() {
  return {{"pneumatic (line 0)", 0, protocol::LineKind::kPressure, 1},
          {"jamming vacuum (line 5, 20 kPa bias)", 5, protocol::LineKind::kVacuum, -1}};
}

/// The random steps' targets on one held-out unit (the steps benchmark's `index`-th of its
/// random units, seed 201 + index): over 0–90 kPa (0 to −90 kPa), at least 3 kPa from the last.
class RandomTargets {
 public:
  RandomTargets(const LineUnderTest& l, int index) : sign_(l.sign), rng_(900 + index) {}
  static uint32_t Unit(int index) { return static_cast<uint32_t>(201 + index); }
  double Next(double at) {
    double to = sign_ * std::round(target_(rng_) / 100) * 100;
    if (std::fabs(to - at) < 3000) to = at + (at * sign_ > 45000 ? -5000 : 5000) * sign_;
    return to;
  }

 private:
  double sign_;
  std::mt19937 rng_;
  std::uniform_real_distribution<double> target_{0, 90000};
};

/// One way of driving the lines, on a plant that may differ from the nominal one.
struct Variant {
  const char* name;
  bool named = true;       ///< also run the named transitions (not only the random steps)
  bool calibrated = true;  ///< the unit's static correction uploaded
  bool trim = true;
  uint32_t slew_pa_per_s = 200000;
  float model_scale = 0;  ///< × the identified chamber lag the board shapes with; 0: no shaping
  float dead_time_scale = 1;  ///< the plant's regulators' dead time
  int32_t overdrive_pa = 30000;
  float flow_scale = 1;  ///< the plant's valves' full flow

  std::unique_ptr<RawLineSession> Open(uint32_t seed) const {
    sim::PlantOptions plant;
    plant.level = 3;
    plant.seed = seed;
    plant.unit = seed;
    plant.dead_time_scale = dead_time_scale;
    plant.flow.flow = flow_scale;
    const Variant v = *this;
    const UnitCalibration& u = CalibrationFor(seed);
    return std::make_unique<RawLineSession>(plant, [v, &u](protocol::ConfigureLine& c) {
      if (!v.trim) c.trim_kp = c.trim_ki_per_s = 0;
      c.slew_pa_per_s = v.slew_pa_per_s;
      if (v.calibrated && !u.correction[c.line].empty()) {
        c.correction_count = static_cast<uint8_t>(u.correction[c.line].size());
        for (size_t i = 0; i < u.correction[c.line].size(); ++i)
          c.correction[i] = u.correction[c.line][i];
      }
      // Misidentified: the air path's model (the regulator's lag and the chamber's) scaled.
      if (v.model_scale > 0 && BoardLagS(u.chamber[c.line]) > 0) {
        c.model_tau_us = static_cast<uint32_t>(v.model_scale * c.model_tau_us);
        c.chamber_tau_us =
            std::max(1u, static_cast<uint32_t>(v.model_scale * BoardLagS(u.chamber[c.line]) * 1e6));
        c.overdrive_pa = v.overdrive_pa;
      }
    });
  }
};

inline std::vector<Variant> Variants() {
  // name, named transitions too, calibrated, trim, slew, air-path model ×, plant dead time ×,
  // overdrive
  return {{"uncalibrated, feed-forward + trim", false, false},
          {"feed-forward only", true, true, false},
          {"feed-forward + trim (today)", true, true, true},
          {"feed-forward + trim, no slew", false, true, true, 0},
          {"+ shaping (identified chamber)", true, true, true, 0, 1, 1, 20000},
          {"shaping, model ×0.5", false, true, true, 0, 0.5f, 1, 20000},
          {"shaping, model ×2", false, true, true, 0, 2, 1, 20000},
          {"shaping, dead time doubled", false, true, true, 0, 1, 2, 20000}};
}

struct ChartPoint {
  std::string line, variant;
  double settle_ms, overshoot_kpa;
};

/// One settling-against-overshoot chart per line kind: docs/steps_<kind>.svg.
inline bool WriteCharts(const std::string& docs, const std::vector<ChartPoint>& points) {
  for (const LineUnderTest& l : Lines()) {
    host::Chart chart;
    chart.title = std::string("Random steps, ") + l.name + ": p95 settling against p95 overshoot";
    chart.x_label = "settling p95 (ms, to max(2 % of the step, 0.5 kPa) for good)";
    chart.y_label = "overshoot p95 (kPa)";
    for (const ChartPoint& p : points) {
      if (p.line != l.name) continue;
      chart.series.push_back({p.variant, {{p.settle_ms, p.overshoot_kpa}}, "", false, true});
    }
    const std::string path = docs + "/steps_" +
                             (l.kind == protocol::LineKind::kVacuum ? "jamming" : "pneumatic") +
                             ".svg";
    if (!host::WriteFileWhole(path, host::RenderSvg(chart)).ok()) return false;
  }
  return true;
}

}  // namespace palpa::bench
