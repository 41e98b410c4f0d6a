// The line step's body, inlined into the board's loop over the lines (a call per line per tick
// otherwise); StepLine (line_pipeline.cc) is the same step for everyone else.
#pragma once

#include "palpa/core/internal/float_ops.h"
#include "palpa/core/line_pipeline.h"
#include "palpa/protocol/enums.h"

namespace palpa::core {
namespace line_step {

/// DAC code + ½ for a commanded pressure (truncation rounds it).
[[gnu::always_inline]] inline float Code(const LineParams& p, float command_pa) {
  return command_pa * p.counts_per_pa + p.counts_at_zero;
}

/// Command that makes the regulator produce `slewed`, from its measured static curve: the rising
/// branch while the command's magnitude grows (from `previous` to `now`: the slewed setpoint, or
/// a shaped step's command, which comes back to the target from beyond it), the falling one
/// while it shrinks (kept while steady). Only lines with a correction track the direction; it is
/// read nowhere else. Inlined: with the lookup in constant time, the call was a sixth of it.
inline float FeedForward(const LineParams& p, LineState& s, float previous, float now,
                         float slewed) {
  const float grown = Abs(now) - Abs(previous);
  if (grown > 0) s.rising = true;
  if (grown < 0) s.rising = false;
  return CorrectionCommand(p.correction, s.rising ? p.correction.rising : p.correction.falling,
                           slewed);
}

/// In a shaped step's hold, after the overdrive: the chamber model closes in on the target from
/// the side the step came from. An outlet on the far side of the target, beyond where the
/// regulator model and the trim put it (by kShapeFallbackPa on both), that was not beyond the
/// target yet as the overdrive began, says the air is faster than the model: the step overshoots.
/// An outlet already beyond as the overdrive began lags an earlier step (slow air, not fast: a
/// vacuum line's outlet creeping toward the pump's pressure is kilopascals short of a deep target
/// after a second), and the overdrive's own push carries it on a little further. The line's steps
/// are unshaped from then on (no overdrive, and a slew limit again: fallback_max_step_pa), until
/// it is configured again. Compares only: the signs are taken once, from the step's direction.
[[gnu::always_inline]] inline void WatchShapedStep(const LineParams& p, LineState& s, float target,
                                                   const LineReading& reading) {
  // The step's direction is the side its overdrive pushed (the chamber estimate follows the
  // outlet, which the overdrive takes beyond the target: it may pass the target too).
  if (!reading.valid) return;
  s.hold_reading_pa = reading.pa;  // where the next overdrive starts from, if one starts now
  const bool up = s.overdrive_up;
  const float outlet = up ? reading.pa : -reading.pa;
  const float beyond_target = (up ? target : -target) + kShapeFallbackPa;
  const float model = s.reference_pa + s.integrator_pa;
  const float beyond_model = (up ? model : -model) + kShapeFallbackPa;
  const float started = up ? s.start_reading_pa : -s.start_reading_pa;
  if (outlet > beyond_target && outlet > beyond_model && started <= beyond_target)
    s.shaping_fell_back = true, s.overdrive_pa = 0, s.max_step_pa = p.fallback_max_step_pa;
}

/// A shaped step's command: what brings the regulator model in one tick to where it should be —
/// the target, or beyond it by the chamber's lead while a slower chamber is short of it — held
/// within the overdrive beyond the target and the line's limits (meeting them adds `saturated` to
/// `status`). The models then move by that
/// command, so the chamber model closes in on the target as fast as the bound allows without
/// passing it; within the trim's dead band the command is the target itself, and the steady-state
/// loop takes over without a bump. The regulator model is open-loop but where a vacuum line's
/// command is held at its upper limit, atmosphere (below); the sensor's reading sets nothing the
/// command follows while it is held there, so nothing winds the model up or makes it ring.
[[gnu::always_inline]] inline float Shape(const LineParams& p, LineState& s, float target,
                                          const LineReading& reading, uint8_t& status,
                                          uint32_t& vents) {
  const float chamber = s.chamber_pa;
  float regulator = s.regulator_pa;
  // regulator + (target + lead × (target − chamber) − regulator) / α (MakeLineParams), the lead
  // the tube's at the target: its lag grows as the absolute pressure falls.
  // The tube's rate now, k (O + C + 2 p_atm): the chamber estimate's below, and the lead's.
  const float outlet = reading.pa;
  const float absolute_sum = outlet + chamber + 2 * kAtmospherePa;
  float command = p.shape_target * target + p.shape_regulator * regulator +
                  p.shape_chamber * chamber + (target - chamber) * (p.lead_gain / absolute_sum);
  // Held within the overdrive, then within the line's limits (meeting them: `saturated`, the
  // step takes longer than the model asked for). The target is within the limits, so a command
  // held below it can only meet the lower one, above it the upper one. The overdrive is beyond
  // the dead band (or none: MakeLineParams), so the dead band matters only within the bounds.
  const float low = target - s.overdrive_pa, high = target + s.overdrive_pa;
  bool below = false, above = false;
  if (command < low) {
    command = low;
    below = command < p.limit_min_pa;
  } else if (command > high) {
    command = high;
    above = command > p.limit_max_pa;
  } else if (Abs(command - target) <= p.dead_band_pa) {
    command = target;
  } else {
    below = command < p.limit_min_pa;
    above = command > p.limit_max_pa;
  }
  if (below) {
    command = p.limit_min_pa;
    status |= protocol::line_status::kSaturated;
  } else if (above) {
    command = p.limit_max_pa;
    status |= protocol::line_status::kSaturated;
    // A vacuum line's step back toward atmosphere held at 0 kPa: its pilot can go no further and
    // its exhaust closes over a 10 kPa band, so the outlet lags the model's lag by kilopascals
    // near atmosphere, and the overdrive would end with the chamber well short. The dump valve
    // lets air in with the exhaust, and the model goes on from the outlet the sensor reads
    // (a pressure line's top limit is no atmosphere: neither; docs/performance.md, "The random
    // jamming steps' misses").
    vents |= p.vent_high_bit;
    regulator += p.model_from_outlet_high * (outlet - regulator);
  }
  s.regulator_pa = regulator + p.model_alpha * (command - regulator);
  // The chamber from the outlet the sensor reads (a shaped line has one; an invalid reading is
  // the last valid one, for the tick before the safe state), through the tube's law:
  // dC/dt = k (O − C)(O + C + 2 p_atm), the difference of the absolute pressures' squares.
  s.chamber_pa = chamber + p.tube_k_dt * (outlet - chamber) * absolute_sum;
  return command;
}

}  // namespace line_step

/// StepLine's body (line_pipeline.h has the contract), for lines with step shaping (kShaping,
/// p.shaping) or without: two copies, so a line that shapes nothing pays nothing for it. Without
/// kCorrection the regulator correction is not looked up (for boards whose lines have none).
template <bool kShaping, bool kCorrection = true>
[[gnu::always_inline]] inline uint32_t StepLineInline(const LineParams& __restrict p,
                                                      LineState& __restrict s, float setpoint_pa,
                                                      const LineReading& __restrict reading,
                                                      LineOutput& __restrict out,
                                                      uint32_t& __restrict vents, uint8_t flags) {
  namespace ls = protocol::line_status;

  uint8_t status = reading.status | flags;
  // 1. Slew limit.
  const float target = Clamp(setpoint_pa, p.limit_min_pa, p.limit_max_pa);
  const float previous = s.slewed_pa;
  float step = target - previous;
  const float max_step = s.max_step_pa;
  if (Abs(step) > max_step) {
    step = step > 0 ? max_step : -max_step;
    status |= ls::kSlewing;
  }
  const float slewed = previous + step;
  s.slewed_pa = slewed;

  // 1b. Step shaping, while a step is under way: beyond the target while the chamber model lags
  // it (the models run while the command is beyond the target or the target moves). The trim
  // holds from then until the reference and the sensor have settled on the target again; then the
  // models are on the target, and a steady line pays for the trim only.
  float wanted = slewed;
  float direction_from = previous;  // where the command moved from (the correction's branch)
  bool held = false;
  if (kShaping && slewed != s.steady_pa) {
    held = true;
    direction_from = s.wanted_pa;
    if (s.wanted_pa != slewed) {  // the models run (the overdrive, or the target moved)
      wanted = line_step::Shape(p, s, slewed, reading, status, vents);
      s.wanted_pa = wanted;
      if (wanted != slewed) {
        s.steady_pa = kUnbounded;  // no setpoint: the step goes on until the hold ends
        status |= ls::kShaping;
      } else if (direction_from != previous) {
        // The overdrive's end (the last tick's command was beyond its target): the hold starts,
        // and the watch compares with where the outlet was as the overdrive began (the overdrive's
        // ticks read nothing). A target that moved without an overdrive leaves the hold as it was.
        s.trim_hold = p.shape_hold_ticks;
        s.start_reading_pa = s.hold_reading_pa;
        s.overdrive_up = direction_from > slewed;
      }
    } else if (s.trim_hold <= 1) {
      s.trim_hold = 0;
      s.steady_pa = s.regulator_pa = s.chamber_pa = slewed;
      s.hold_reading_pa = reading.pa;  // settled: where the next overdrive starts from
    } else {
      --s.trim_hold;
      line_step::WatchShapedStep(p, s, slewed, reading);  // the overdrive is over
    }
  }

  // 2. Regulator model (dead time + lag) of what the regulator is commanded: the reference the
  // trim compares the sensor with: the command of the dead time ago (this tick's when none), from
  // a ring of the last kMaxDeadTicks commands.
  const uint8_t index = s.delay_index;
  s.delay[index] = wanted;
  const float delayed = s.delay[(index - p.delay_ticks) & (kMaxDeadTicks - 1)];
  s.delay_index = static_cast<uint8_t>((index + 1) & (kMaxDeadTicks - 1));
  s.reference_pa += p.model_alpha * (delayed - s.reference_pa);

  // 3. Below the regulator's minimum set pressure: command 0, integrator off, and the dump valve
  // open where the line vents (the outlet goes to atmosphere, no further).
  if (Abs(slewed) < p.regulator_min_pa) {
    vents |= p.vent_bit;
    s.integrator_pa = 0;
    out.command_pa = 0;
    out.status = status | ls::kOpenLoop;
    return p.zero_counts;
  }

  // 4. Feed-forward through the static correction (the nominal scaling without one), plus the PI
  // trim where a sensor reads.
  // A shaped step's overdrive rides on the target's corrected command (the correction's points
  // need not reach beyond the target).
  float command =
      kCorrection && p.correction.count >= 2
          ? line_step::FeedForward(p, s, direction_from, wanted, slewed) + (wanted - slewed)
          : wanted;
  float integrator = s.integrator_pa;
  if (kShaping && reading.valid && held) {
    // Held through a shaped step: the outlet lags an overdriven reference by the flow it passes,
    // which is no static error for the trim to learn. What it learnt stays on.
    command += integrator;
  } else if (reading.valid) {
    const float error = s.reference_pa - reading.pa;
    const float effective = Abs(error) <= p.dead_band_pa ? 0.0f : error;
    integrator += p.ki_dt * effective;
    float trim = p.kp * effective + integrator;
    // Back-calculation at the authority clamp: the integrator gives up what the clamp cut (one
    // compare in the common case, inside the authority).
    if (Abs(trim) > p.authority_pa) {
      const float clamp = trim > 0 ? p.authority_pa : -p.authority_pa;
      integrator += clamp - trim;
      trim = clamp;
      status |= ls::kTrimClamped;
    }
    command += trim;
  } else {
    status |= ls::kOpenLoop;
  }

  // 5. Final clamp to the line's limits, with back-calculation into the integrator.
  if (command < p.limit_min_pa || command > p.limit_max_pa) {
    const float limit = command < p.limit_min_pa ? p.limit_min_pa : p.limit_max_pa;
    // A shaped step's overdrive meeting the limit is no reason for the trim to unlearn.
    if (!kShaping || !held)
      integrator = Clamp(integrator + (limit - command), -p.authority_pa, p.authority_pa);
    command = limit;
    status |= ls::kSaturated;
  }
  s.integrator_pa = integrator;
  out.command_pa = command;
  out.status = status;
  // Within the limits, so within the command range: a code between the signal's ends.
  return static_cast<uint32_t>(line_step::Code(p, command));
}

/// StepLineInline for the line's kind of step; `flags` are status bits the caller adds (ORed in
/// with the step's own, so the status is stored once). Without kCorrection, for lines without a
/// regulator correction only.
template <bool kCorrection = true>
[[gnu::always_inline]] inline uint32_t StepLineEither(const LineParams& p, LineState& s,
                                                      float setpoint_pa, const LineReading& reading,
                                                      LineOutput& out, uint32_t& vents,
                                                      uint8_t flags = 0) {
  return p.shaping
             ? StepLineInline<true, kCorrection>(p, s, setpoint_pa, reading, out, vents, flags)
             : StepLineInline<false, kCorrection>(p, s, setpoint_pa, reading, out, vents, flags);
}

}  // namespace palpa::core
