// Frequency response and time-domain run of one pressure line's loop.
#include "pressure_loop.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <deque>

#include "palpa/core/line_pipeline.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::testing {
namespace {

constexpr double kT = 0.001;  // tick
constexpr double kFullScale = 100000;

std::complex<double> Lag(double tau, std::complex<double> z_inverse) {
  const double a = kT / (tau + kT);
  return a / (1.0 - (1.0 - a) * z_inverse);
}

}  // namespace

Margins LoopMargins(const LoopCase& c) {
  Margins m{180, 200, 0};
  const double kp = c.gain * c.kp, ki_dt = c.gain * c.ki * kT;
  const int delay = 1 + static_cast<int>(std::lround(c.dead_time_s / kT));
  double previous_phase = 0;
  bool found_gain = false, found_phase = false;
  for (double w = 0.01; w < M_PI / kT; w *= 1.002) {
    const std::complex<double> zi = std::polar(1.0, -w * kT);
    const std::complex<double> controller = kp + ki_dt / (1.0 - zi);
    const std::complex<double> plant =
        std::pow(zi, delay) * Lag(c.regulator_tau_s, zi) * Lag(c.chamber_tau_s, zi);
    const std::complex<double> loop = controller * plant;
    // Unwrapped phase: the delay keeps turning it past -180° as w grows.
    double phase = std::arg(loop) * 180 / M_PI;
    while (phase > previous_phase + 180) phase -= 360;
    while (phase < previous_phase - 180) phase += 360;
    previous_phase = phase;
    if (!found_gain && std::abs(loop) < 1) {
      m.phase_deg = 180 + phase;
      m.crossover_hz = w / (2 * M_PI);
      found_gain = true;
    }
    if (!found_phase && phase <= -180) {
      m.gain_db = -20 * std::log10(std::abs(loop));
      found_phase = true;
    }
  }
  return m;
}

double SettledRipple(const LoopCase& c, int seconds) {
  protocol::ConfigureLine line{};
  line.kind = protocol::LineKind::kPressure;
  line.dac_bits = 12;
  line.command_min_pa = 0;
  line.command_max_pa = static_cast<int32_t>(kFullScale);
  line.limit_max_pa = static_cast<int32_t>(kFullScale);
  line.regulator_min_pa = 1000;
  line.sensor = protocol::SensorKind::kAnalog;
  line.trim_kp = c.gain * c.kp;
  line.trim_ki_per_s = c.gain * c.ki;
  line.trim_authority_pa = 5000;
  line.trim_dead_band_pa = static_cast<int32_t>(c.trim_dead_band * kFullScale);
  line.model_tau_us = static_cast<uint32_t>(c.regulator_tau_s * 1e6);
  line.model_dead_time_us = static_cast<uint32_t>(c.dead_time_s * 1e6);
  const core::LineParams p = core::MakeLineParams(line, 1000);
  core::LineState s;
  core::ResetLineState(p, s, 0);
  // Plant: a regulator that ignores command moves within its dead band (backlash), a static gain
  // error the trim must remove, dead time, lag; then the chamber the sensor sits behind.
  std::deque<double> pipe(static_cast<size_t>(std::lround(c.dead_time_s / kT)) + 1, 0.0);
  double held = 0, outlet = 0, chamber = 0, low = 1e9, high = -1e9;
  const double band = c.valve_dead_band * kFullScale;
  const int ticks = seconds * 1000;
  for (int k = 0; k < ticks; ++k) {
    core::LineOutput out;
    core::StepLine(p, s, 50000, core::LineReading{true, 0, static_cast<float>(chamber)}, out);
    const double command = 1.01 * out.command_pa + 300;  // the regulator's own static error
    if (command > held + band / 2) held = command - band / 2;
    if (command < held - band / 2) held = command + band / 2;
    pipe.push_back(held);
    const double delayed = pipe.front();
    pipe.pop_front();
    outlet += kT / (c.regulator_tau_s + kT) * (delayed - outlet);
    chamber += kT / (c.chamber_tau_s + kT) * (outlet - chamber);
    if (!std::isfinite(chamber)) return 1e9;
    if (k >= ticks - 5000) {
      low = std::min(low, chamber);
      high = std::max(high, chamber);
    }
  }
  return (high - low) / kFullScale;
}

}  // namespace palpa::testing
