// What the plant's tests share: a thesis-5finger plant at a level, and holding a line's command.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/plant.h"

namespace palpa::sim::testing {

namespace ps = palpa::sim;

inline ps::Plant MakePlant(int level, uint32_t unit = 0, uint32_t seed = 1, bool errors = true,
                           ps::Effects effects = {}) {
  const auto& c = *palpa::core::FindBoardConfig("thesis-5finger");
  ps::PlantOptions o;
  o.level = level;
  o.unit = unit;
  o.seed = seed;
  o.static_errors = errors;
  o.effects = effects;
  ps::Plant plant(c.lines.data(), c.line_count, c.fingers.data(), c.finger_count, o);
  plant.SetVented(false);
  return plant;
}

inline uint32_t CountsFor(float pa) {
  return static_cast<uint32_t>(pa / 100000.0f * 4095.0f + 0.5f);
}

inline void Hold(ps::Plant& plant, uint8_t line, float pa, int ms) {
  plant.SetDacCounts(line, CountsFor(std::fabs(pa)));
  for (int i = 0; i < ms; ++i) plant.Step();
}

inline double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxy / sxx;
}

}  // namespace palpa::sim::testing
