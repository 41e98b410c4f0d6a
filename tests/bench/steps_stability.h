// Where shaped steps fail: random steps with the chamber model misidentified, the regulators'
// dead time longer and their valves' flow smaller or larger than the plant the model was
// identified on; in each cell, whether the chamber overshoots, rings or never settles, whether
// the board said `saturated`, and whether it fell back to unshaped steps.
#pragma once

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "steps_measure.h"
#include "steps_variants.h"

namespace palpa::bench {

struct StabilityCell {
  double p95_ms = 0, overshoot_kpa = 0;
  int never = 0, rings = 0, steps = 0, saturated = 0, fell_back = 0;
};

/// Random steps (1 s dwells) on two held-out units for one plant and model.
inline StabilityCell RunCell(const LineUnderTest& l, float model, float dead, float flow) {
  Variant v{"map", false, true, true, 0, model, dead, 20000, flow};
  StabilityCell c;
  std::vector<double> settle, over;
  for (uint32_t unit = 0; unit < 2; ++unit) {
    const auto session = v.Open(301 + unit);
    l.Hold(*session);
    std::mt19937 rng(700 + unit);
    std::uniform_real_distribution<double> target(0, 90000);
    double at = 0;
    for (int i = 0; i < 20; ++i) {
      double to = l.sign * std::round(target(rng) / 100) * 100;
      if (std::fabs(to - at) < 3000) to = at + (at * l.sign > 45000 ? -5000 : 5000) * l.sign;
      const StepFigures f = RunStep(*session, l.line, at, to, 1000);
      settle.push_back(f.settle_ms);
      over.push_back(f.overshoot_pa);
      c.never += f.settle_ms == kNever;
      c.rings += f.crossings >= 2;
      c.saturated += f.saturated;
      ++c.steps;
      at = to;
    }
    c.fell_back += session->ShapingFellBack(l.line);
  }
  c.p95_ms = Quantile(settle, 0.95);
  c.overshoot_kpa = Quantile(over, 0.95) / 1000;
  return c;
}

/// One Markdown table per line: rows the model's error and the dead time, columns the flow.
inline std::string StabilityMap(const LineUnderTest& l) {
  const float flows[] = {0.5f, 1, 2};
  std::string t =
      std::string("**") + l.name +
      "** — each cell: p95 settling (ms) / p95 overshoot (kPa); steps that rang "
      "(crossed the band twice), never settled within 1 s, said `saturated`; units (of 2) whose "
      "shaped steps fell back to unshaped ones:\n\n"
      "| model × | dead time × | flow ×0.5 | flow ×1 | flow ×2 |\n|---|---|---|---|---|\n";
  for (float model : {0.5f, 1.0f, 2.0f, 4.0f}) {
    for (float dead : {1.0f, 2.0f, 4.0f}) {
      char row[64];
      std::snprintf(row, sizeof(row), "| %.1f | %.0f |", model, dead);
      t += row;
      for (float flow : flows) {
        const StabilityCell c = RunCell(l, model, dead, flow);
        char cell[192];
        std::snprintf(cell, sizeof(cell), " %s / %.1f; %d rang, %d never, %d sat., %d fell back |",
                      c.p95_ms == kNever ? "never" : std::to_string(std::lround(c.p95_ms)).c_str(),
                      c.overshoot_kpa, c.rings, c.never, c.saturated, c.fell_back);
        t += cell;
      }
      t += "\n";
    }
  }
  return t;
}

}  // namespace palpa::bench
