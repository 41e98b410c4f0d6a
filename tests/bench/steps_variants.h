// What the step benchmark compares: the lines it steps and the ways of driving them (feed-forward
// alone, with the trim), and the settling-against-overshoot charts it draws from them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "raw_line_session.h"

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

/// One way of driving the lines, on a plant that may differ from the nominal one.
struct Variant {
  const char* name;
  bool named = true;  ///< also run the named transitions (not only the random steps)
  bool trim = true;
  float dead_time_scale = 1;  ///< the plant's regulators' dead time
  uint32_t slew_pa_per_s = 200000;
  uint32_t chamber_tau_us = 0;  ///< the chamber model the board shapes steps with; 0: none
  int32_t overdrive_pa = 0;

  std::unique_ptr<RawLineSession> Open(uint32_t seed) const {
    sim::PlantOptions plant;
    plant.level = 3;
    plant.seed = seed;
    plant.unit = seed;
    plant.dead_time_scale = dead_time_scale;
    const Variant v = *this;
    return std::make_unique<RawLineSession>(plant, [v](protocol::ConfigureLine& c) {
      if (!v.trim) c.trim_kp = c.trim_ki_per_s = 0;
      c.slew_pa_per_s = v.slew_pa_per_s;
      c.chamber_tau_us = v.chamber_tau_us;
      c.overdrive_pa = v.overdrive_pa;
    });
  }
};

inline std::vector<Variant> Variants() {
  // name, named transitions too, trim, plant dead time ×, slew, chamber lag (µs), overdrive (Pa)
  return {{"feed-forward only", true, false},
          {"feed-forward + trim (today)", true, true},
          {"feed-forward + trim, no slew", false, true, 1, 0},
          {"+ shaping (chamber lag 20 ms)", true, true, 1, 0, 20000, 30000},
          {"shaping, model ×0.5", false, true, 1, 0, 10000, 30000},
          {"shaping, model ×2", false, true, 1, 0, 40000, 30000},
          {"shaping, dead time doubled", false, true, 2, 0, 20000, 30000}};
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
    if (!host::WriteFileWhole(path, host::RenderSvg(chart))) return false;
  }
  return true;
}

}  // namespace palpa::bench
