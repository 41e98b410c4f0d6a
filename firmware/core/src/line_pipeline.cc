// The line pipeline: the only code between a setpoint and a DAC code.
#include "palpa/core/line_pipeline.h"

#include "line_step.h"
#include "palpa/core/ceilings.h"
#include "palpa/core/internal/float_ops.h"
#include "palpa/protocol/enums.h"

namespace palpa::core {
namespace ls = protocol::line_status;

LineParams MakeLineParams(const protocol::ConfigureLine& line, uint32_t tick_us) {
  LineParams p;
  const Ceiling ceiling = CeilingFor(line.kind);
  const float dt = static_cast<float>(tick_us) * 1e-6f;
  p.has_sensor = line.sensor == protocol::SensorKind::kAnalog;
  // Per configuration, not per tick: the span check and the scale of the sensor reading.
  const uint32_t margin = (line.sensor_counts_max - line.sensor_counts_min) / 50;
  p.sensor_counts_low = line.sensor_counts_min > margin ? line.sensor_counts_min - margin : 0;
  p.sensor_counts_high = line.sensor_counts_max + margin;
  p.sensor_min_pa = static_cast<float>(line.sensor_min_pa);
  p.sensor_counts_min = static_cast<float>(line.sensor_counts_min);
  p.sensor_pa_per_count = static_cast<float>(line.sensor_max_pa - line.sensor_min_pa) /
                          static_cast<float>(line.sensor_counts_max - line.sensor_counts_min);
  // The limits within the hard ceiling and within the regulator's command range (validation
  // refuses limits beyond either; intersected here too, because the step converts a command held
  // to the limits into a DAC code without a clamp of its own).
  const Ceiling command = CommandRange(line.command_min_pa, line.command_max_pa);
  const int32_t floor = ceiling.min_pa > command.min_pa ? ceiling.min_pa : command.min_pa;
  const int32_t top = ceiling.max_pa < command.max_pa ? ceiling.max_pa : command.max_pa;
  p.limit_min_pa = static_cast<float>(line.limit_min_pa > floor ? line.limit_min_pa : floor);
  p.limit_max_pa = static_cast<float>(line.limit_max_pa < top ? line.limit_max_pa : top);
  p.safe_pa = Clamp(static_cast<float>(line.safe_pa), p.limit_min_pa, p.limit_max_pa);
  // No slew limit is a step no setpoint change can exceed (one compare a tick instead of two).
  p.max_step_pa = line.slew_pa_per_s > 0 ? static_cast<float>(line.slew_pa_per_s) * dt : kUnbounded;
  p.fallback_max_step_pa = line.slew_pa_per_s > 0 ? p.max_step_pa : kFallbackSlewPaPerS * dt;
  p.regulator_min_pa = static_cast<float>(line.regulator_min_pa);
  p.pump_below_pa = line.kind == protocol::LineKind::kVacuum ? -p.regulator_min_pa : -kUnbounded;
  // 0 % to 100 % of the signal spans the command range; a 4-20 mA output is a 0-20 mA DAC, so
  // 0 % of the signal is 4 mA, a fifth of full scale.
  const float max_counts = static_cast<float>((1u << line.dac_bits) - 1u);
  const float counts_low =
      line.dac_signal == protocol::SignalRange::kMilliamp4To20 ? 0.2f * max_counts : 0.0f;
  const float command_min = static_cast<float>(line.command_min_pa);
  const float command_span = static_cast<float>(line.command_max_pa - line.command_min_pa);
  p.counts_per_pa = command_span != 0 ? (max_counts - counts_low) / command_span : 0.0f;
  p.counts_at_zero = counts_low - command_min * p.counts_per_pa + 0.5f;
  p.rounded_low = counts_low + 0.5f;
  p.rounded_high = max_counts;  // truncates to the top code like anything up to it + ½
  p.kp = line.trim_kp;
  p.ki_dt = line.trim_ki_per_s * dt;
  p.authority_pa = static_cast<float>(line.trim_authority_pa);
  p.dead_band_pa = static_cast<float>(line.trim_dead_band_pa);
  const float tau = static_cast<float>(line.model_tau_us) * 1e-6f;
  p.model_alpha = tau > 0 ? dt / (tau + dt) : 1.0f;
  const uint32_t dead = tick_us > 0 ? (line.model_dead_time_us + tick_us / 2) / tick_us : 0;
  p.delay_ticks = static_cast<uint8_t>(dead < kMaxDeadTicks ? dead : kMaxDeadTicks - 1);
  // Step shaping: a model of the chamber's lag, inverted (line_step.h).
  const float chamber_tau = static_cast<float>(line.chamber_tau_us) * 1e-6f;
  // The chamber is estimated from the outlet's reading: no shaping where no sensor reads it (an
  // invalid reading of a line with one raises the implausible-sensor fault the same tick).
  p.shaping = line.chamber_tau_us > 0 && line.overdrive_pa > 0 && p.has_sensor;
  // The regulator model's lag inverted: command = R + (target + lead (target − C) − R) / α,
  // its products taken here, once, instead of every tick.
  const float gain = 1.0f / p.model_alpha;
  p.shape_target = gain;
  p.shape_chamber = 0;
  p.shape_regulator = 1.0f - gain;
  // The tube's law: dC/dt = k (O − C)(O + C + 2 p_atm), its lag τ = 1 / (k S) with S the sum of
  // the absolute pressures; chamber_tau_us is the lag at the calibration step's mean pressure
  // (S = 2 (p_step + p_atm)). The estimate moves by k dt S (O − C) a tick (explicit: dt/τ, not
  // one lag's dt/(τ + dt)), so the lead that makes it close α of its gap a tick, the regulator
  // model's own rate, is α τ/dt − 1 at the tube's rate now; over α (the command's 1/α):
  // 1 / (k dt S) − 1/α. With one lag's lead, (τ − τ_r) / (τ_r + dt) = α τ/dt − (1 − α), the
  // estimate closed faster than the lead assumed: the regulator model's wanted lead fell faster
  // than it could follow, and the command crossed the target for a tick as the overdrive ended.
  // On where the chamber is slower than the regulator at every pressure within the limits (the
  // lead then never below 0), else no lead.
  if (p.shaping && chamber_tau > 0 && dt > 0) {
    const float at = ChamberStepMeanPa(line.kind) + kAtmospherePa;
    float k_dt = dt / (chamber_tau * 2.0f * at);
    // Explicit, so at most a tick's full step at the line's highest absolute pressure.
    const float highest = p.limit_max_pa + kAtmospherePa;
    if (k_dt * 2.0f * highest > 1.0f) k_dt = 1.0f / (2.0f * highest);
    p.tube_k_dt = k_dt;
    const float lead_gain = 1.0f / k_dt;
    const float lead_offset = gain;
    if (lead_gain / (2.0f * highest) >= lead_offset) {
      p.lead_gain = lead_gain;
      // − lead_offset × (target − chamber), taken into the target's and the chamber's factors.
      p.shape_target -= lead_offset;
      p.shape_chamber = lead_offset;
    }
  }
  // An overdrive within the trim's dead band would only ever command the target (line_step.h).
  const float overdrive = static_cast<float>(line.overdrive_pa);
  p.overdrive_pa = p.shaping && overdrive > p.dead_band_pa ? overdrive : 0.0f;
  // The regulator model's dead time and three lags of it and the chamber: the reference and the
  // sensor settle on the target again before the trim compares them.
  const float settle_ticks = dt > 0 ? 3.0f * (tau + chamber_tau) / dt : 0.0f;
  p.shape_hold_ticks =
      p.shaping
          ? static_cast<uint16_t>(p.delay_ticks + 1 + (settle_ticks < 60000 ? settle_ticks : 60000))
          : 0;
  // Venting toward atmosphere, where atmosphere lies within the line's limits: the dump valve
  // cannot take the line beyond them, nor beyond its target (below the regulator's minimum the
  // command is 0 already).
  const bool holds_atmosphere = p.limit_min_pa <= 0 && p.limit_max_pa >= 0;
  p.vent_bit = p.shaping && holds_atmosphere && p.regulator_min_pa > 0 ? 1u << line.line : 0u;
  p.vent_high_bit = p.limit_max_pa == 0 ? p.vent_bit : 0u;
  p.model_from_outlet_high = p.vent_high_bit != 0 ? 1.0f : 0.0f;
  MakeCorrection(line.correction.data(), line.correction_count, p.correction);
  p.safe_counts = CountsFor(p, p.safe_pa);
  p.zero_counts = CountsFor(p, 0);
  return p;
}

void ResetLineState(const LineParams& p, LineState& s, float pa) {
  s.slewed_pa = pa;
  s.integrator_pa = 0;
  s.reference_pa = pa;
  // Only the slots read before they are written again: the dead time's behind the next write
  // (the safe path runs this every tick).
  for (uint8_t k = 1; k <= p.delay_ticks; ++k) s.delay[kMaxDeadTicks - k] = pa;
  s.delay_index = 0;
  s.wanted_pa = pa;
  s.steady_pa = pa;
  s.regulator_pa = pa;
  s.chamber_pa = pa;
  s.hold_reading_pa = pa;  // held there: where a first overdrive starts from
  s.trim_hold = 0;
  s.rising = true;
  s.overdrive_pa = s.shaping_fell_back ? 0.0f : p.overdrive_pa;
  s.max_step_pa = s.shaping_fell_back ? p.fallback_max_step_pa : p.max_step_pa;
}

uint32_t CountsFor(const LineParams& p, float command_pa) {
  return static_cast<uint32_t>(
      Clamp(line_step::Code(p, command_pa), p.rounded_low, p.rounded_high));
}

uint32_t HoldLineSafe(const LineParams& p, LineState& s, const LineReading& reading,
                      LineOutput& out) {
  // Critical for safety: the shutdown bypasses slew, trim and model.
  ResetLineState(p, s, p.safe_pa);
  out.command_pa = p.safe_pa;
  out.status = ls::kSafe | ls::kOpenLoop | reading.status;
  return p.safe_counts;
}

uint32_t StepLine(const LineParams& p, LineState& s, float setpoint_pa, const LineReading& reading,
                  LineOutput& out, uint32_t* vents) {
  uint32_t vented = 0;
  const uint32_t code = StepLineEither(p, s, setpoint_pa, reading, out, vented);
  if (vents != nullptr) *vents |= vented;
  return code;
}

}  // namespace palpa::core
