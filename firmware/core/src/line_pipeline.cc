// The line pipeline: the only code between a setpoint and a DAC code.
#include "palpa/core/line_pipeline.h"

#include "float_ops.h"
#include "palpa/core/ceilings.h"
#include "palpa/core/curve.h"
#include "palpa/protocol/enums.h"

namespace palpa::core {
namespace {

namespace ls = protocol::line_status;

/// DAC code for a commanded pressure; inlined into the step (a call per line per tick otherwise).
[[gnu::always_inline]] inline uint32_t Counts(const LineParams& p, float command_pa) {
  const float fraction = Clamp((command_pa - p.command_min_pa) / p.command_span_pa, 0.0f, 1.0f);
  const float counts = p.counts_low + fraction * (p.counts_high - p.counts_low) + 0.5f;
  return counts >= static_cast<float>(p.max_counts) ? p.max_counts : static_cast<uint32_t>(counts);
}

/// Command that makes the regulator produce `pa`, from its measured static curve (rising or
/// falling branch); the nominal scaling when the line has no correction.
float FeedForward(const LineParams& p, float pa, bool rising) {
  if (p.correction_count < 2) return pa;
  const float* produced = rising ? p.correction_rising.data() : p.correction_falling.data();
  return Interpolate(produced, p.correction_command.data(), p.correction_count, pa);
}

}  // namespace

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
  p.limit_min_pa =
      static_cast<float>(line.limit_min_pa > ceiling.min_pa ? line.limit_min_pa : ceiling.min_pa);
  p.limit_max_pa =
      static_cast<float>(line.limit_max_pa < ceiling.max_pa ? line.limit_max_pa : ceiling.max_pa);
  p.safe_pa = Clamp(static_cast<float>(line.safe_pa), p.limit_min_pa, p.limit_max_pa);
  // No slew limit is a step no setpoint change can exceed (one compare a tick instead of two).
  p.max_step_pa = line.slew_pa_per_s > 0 ? static_cast<float>(line.slew_pa_per_s) * dt : kUnbounded;
  p.regulator_min_pa = static_cast<float>(line.regulator_min_pa);
  p.pump_below_pa = line.kind == protocol::LineKind::kVacuum ? -p.regulator_min_pa : -kUnbounded;
  p.command_min_pa = static_cast<float>(line.command_min_pa);
  p.command_span_pa = static_cast<float>(line.command_max_pa - line.command_min_pa);
  p.max_counts = (1u << line.dac_bits) - 1u;
  // A 4-20 mA output is a 0-20 mA DAC: 0 % of the signal is 4 mA, a fifth of full scale.
  p.counts_low = line.dac_signal == protocol::SignalRange::kMilliamp4To20
                     ? 0.2f * static_cast<float>(p.max_counts)
                     : 0.0f;
  p.counts_high = static_cast<float>(p.max_counts);
  p.kp = line.trim_kp;
  p.ki_dt = line.trim_ki_per_s * dt;
  p.authority_pa = static_cast<float>(line.trim_authority_pa);
  p.dead_band_pa = static_cast<float>(line.trim_dead_band_pa);
  const float tau = static_cast<float>(line.model_tau_us) * 1e-6f;
  p.model_alpha = tau > 0 ? dt / (tau + dt) : 1.0f;
  const uint32_t dead = tick_us > 0 ? (line.model_dead_time_us + tick_us / 2) / tick_us : 0;
  p.dead_ticks = static_cast<uint8_t>(dead < kMaxDeadTicks ? dead : kMaxDeadTicks - 1);
  p.correction_count = line.correction_count;
  for (uint8_t i = 0; i < line.correction_count; ++i) {
    p.correction_command[i] = static_cast<float>(line.correction[i].command_pa);
    p.correction_rising[i] = static_cast<float>(line.correction[i].rising_pa);
    p.correction_falling[i] = static_cast<float>(line.correction[i].falling_pa);
  }
  p.safe_counts = CountsFor(p, p.safe_pa);
  p.zero_counts = CountsFor(p, 0);
  return p;
}

void ResetLineState(const LineParams& p, LineState& s, float pa) {
  s.slewed_pa = pa;
  s.integrator_pa = 0;
  s.reference_pa = pa;
  for (float& d : s.delay) d = pa;
  s.delay_index = 0;
  s.rising = true;
  (void)p;
}

uint32_t CountsFor(const LineParams& p, float command_pa) { return Counts(p, command_pa); }

void StepLine(const LineParams& p, LineState& s, const LineInput& in, LineOutput& out) {
  if (in.safe) {  // Critical for safety: the shutdown bypasses slew, trim and model.
    ResetLineState(p, s, p.safe_pa);
    out.command_pa = p.safe_pa;
    out.counts = p.safe_counts;
    out.status = ls::kSafe | ls::kOpenLoop;
    return;
  }
  out.status = 0;
  // 1. Slew limit.
  const float target = Clamp(in.setpoint_pa, p.limit_min_pa, p.limit_max_pa);
  float step = target - s.slewed_pa;
  if (Abs(step) > p.max_step_pa) {
    step = step > 0 ? p.max_step_pa : -p.max_step_pa;
    out.status |= ls::kSlewing;
  }
  const float previous = s.slewed_pa;
  s.slewed_pa += step;
  const float grown = Abs(s.slewed_pa) - Abs(previous);  // kept while steady
  if (grown > 0) s.rising = true;
  if (grown < 0) s.rising = false;

  // 2. Regulator model (dead time + lag): the reference the trim compares the sensor with.
  const float delayed = s.delay[s.delay_index];
  s.delay[s.delay_index] = s.slewed_pa;
  s.delay_index = static_cast<uint8_t>(s.delay_index + 1 >= p.dead_ticks ? 0 : s.delay_index + 1);
  s.reference_pa += p.model_alpha * ((p.dead_ticks == 0 ? s.slewed_pa : delayed) - s.reference_pa);

  // 3. Below the regulator's minimum set pressure: command 0, integrator off.
  if (Abs(s.slewed_pa) < p.regulator_min_pa) {
    s.integrator_pa = 0;
    out.command_pa = 0;
    out.counts = p.zero_counts;
    out.status |= ls::kOpenLoop;
    return;
  }

  // 4. Feed-forward through the static correction, plus the PI trim where a sensor exists.
  const float feed_forward = FeedForward(p, s.slewed_pa, s.rising);
  float trim = 0;
  if (p.has_sensor && in.measured_valid) {
    const float error = s.reference_pa - in.measured_pa;
    const float effective = Abs(error) <= p.dead_band_pa ? 0.0f : error;
    s.integrator_pa += p.ki_dt * effective;
    const float unclamped = p.kp * effective + s.integrator_pa;
    trim = Clamp(unclamped, -p.authority_pa, p.authority_pa);
    if (trim != unclamped) {
      s.integrator_pa += trim - unclamped;  // back-calculation at the authority clamp
      out.status |= ls::kTrimClamped;
    }
  } else {
    out.status |= ls::kOpenLoop;
  }

  // 5. Final clamp to the line's limits, with back-calculation into the integrator.
  const float unclamped_command = feed_forward + trim;
  out.command_pa = Clamp(unclamped_command, p.limit_min_pa, p.limit_max_pa);
  if (out.command_pa != unclamped_command) {
    s.integrator_pa = Clamp(s.integrator_pa + (out.command_pa - unclamped_command), -p.authority_pa,
                            p.authority_pa);
    out.status |= ls::kSaturated;
  }
  out.counts = Counts(p, out.command_pa);
}

}  // namespace palpa::core
