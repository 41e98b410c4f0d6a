// What the shaped-step tests share: a shaped pressure line's and a vacuum line's configurations,
// a regulator with a chamber behind it to close the loop, and a line under test.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>

#include "palpa/core/line_pipeline.h"

namespace step_shaping {

namespace pc = palpa::core;
namespace pp = palpa::protocol;

inline pp::ConfigureLine ShapedLine(uint32_t chamber_tau_us = 20000, int32_t overdrive_pa = 30000) {
  pp::ConfigureLine c{};
  c.kind = pp::LineKind::kPressure;
  c.dac_bits = 12;
  c.command_min_pa = 0;
  c.command_max_pa = c.limit_max_pa = 100000;
  c.regulator_min_pa = 1000;
  c.sensor = pp::SensorKind::kAnalog;
  c.trim_kp = 0.1f;
  c.trim_ki_per_s = 1.0f;
  c.trim_authority_pa = 5000;
  c.trim_dead_band_pa = 100;
  c.model_tau_us = 20000;
  c.model_dead_time_us = 5000;
  c.chamber_tau_us = chamber_tau_us;
  c.overdrive_pa = overdrive_pa;
  return c;
}

/// A shaped vacuum line 5: its commands from 0 to −100 kPa, its limits −90 … 0 kPa.
inline pp::ConfigureLine VacuumLine() {
  pp::ConfigureLine c = ShapedLine();
  c.line = 5;
  c.kind = pp::LineKind::kVacuum;
  c.command_min_pa = 0;
  c.command_max_pa = -100000;
  c.limit_min_pa = -90000;
  c.limit_max_pa = 0;
  return c;
}

/// A regulator (dead time, pilot lag, outlet moving at most `rate` Pa a tick: its valve's flow)
/// and a chamber lagging the outlet; the sensor reads the outlet, as on the board.
struct Air {
  std::deque<float> pipe;
  float pilot = 0, outlet = 0, chamber = 0, chamber_alpha, rate;
  Air(int dead_ticks, float chamber_tau_s, float rate_pa_per_tick = 1e9f)
      : pipe(static_cast<size_t>(dead_ticks), 0.0f),
        chamber_alpha(0.001f / (chamber_tau_s + 0.001f)),
        rate(rate_pa_per_tick) {}
  void Step(float command) {
    pipe.push_back(command);
    const float delayed = pipe.front();
    pipe.pop_front();
    pilot += (0.001f / 0.021f) * (delayed - pilot);
    outlet += std::clamp(pilot - outlet, -rate, rate);
    chamber += chamber_alpha * (outlet - chamber);
  }
};

/// A line under test: its parameters from a configuration (1 ms ticks) and its state holding
/// `from_pa`; a test binds its parts, auto& [p, s, out] = line.
struct LineUnderTest {
  const pc::LineParams p;
  pc::LineState s;
  pc::LineOutput out;
  LineUnderTest(const pp::ConfigureLine& c, float from_pa) : p(pc::MakeLineParams(c, 1000)) {
    pc::ResetLineState(p, s, from_pa);
  }
};

inline float Run(const pc::LineParams& p, pc::LineState& s, float setpoint, float measured,
                 pc::LineOutput& out) {
  pc::StepLine(p, s, setpoint, pc::LineReading{true, 0, measured}, out);
  return out.command_pa;
}

}  // namespace step_shaping
