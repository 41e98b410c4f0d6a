// One regulated line per tick (2-DOF): slew → step shaping → feed-forward through the static
// correction → PI trim against the regulator-model reference → final clamp → DAC counts. Pure.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/correction_lookup.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::core {

inline constexpr uint8_t kMaxDeadTicks = 32;  ///< a power of two: the delay line is a ring
static_assert((kMaxDeadTicks & (kMaxDeadTicks - 1)) == 0);

/// After a shaped step's overdrive, how far the outlet may go beyond both the target and the
/// regulator model's reference (the trim's part taken off), on the far side from where the step
/// came, before the line falls back to unshaped steps. On the steps benchmark's held-out units
/// (level 3) no model with the right lags, lags half too short, twice the dead time or the
/// valves' flow halved or doubled falls back; lags 1.5 × or 2 × too long do, on their first
/// steps (docs/performance.md, "Fast steps").
inline constexpr float kShapeFallbackPa = 2000;

/// The slew a line whose shaped steps fell back runs with where its own is none (a shaped line's
/// calibration sets it to 0): the compiled-in configurations' default, which keeps an unshaped
/// line's trim from learning each step's transient (docs/performance.md, "The slew default").
inline constexpr float kFallbackSlewPaPerS = 200000;

/// The atmosphere the chamber's tube law takes gauge pressures from (Pa absolute).
inline constexpr float kAtmospherePa = 101325;

/// The mean gauge pressure of the calibration's chamber step for a line of `kind`, where its lag
/// (ConfigureLine::chamber_tau_us) holds: 5 → 20 kPa of vacuum, 20 → 40 kPa.
constexpr float ChamberStepMeanPa(protocol::LineKind kind) {
  return kind == protocol::LineKind::kVacuum ? -12500.0f : 30000.0f;
}

/// Per-line constants, derived once from a ConfigureLine when it is applied.
struct LineParams {
  bool has_sensor = false;
  /// ADC counts inside the sensor's output span (with a 2 % margin); outside is an open or
  /// shorted wire, not a pressure. Counts convert as sensor_min_pa + (counts − counts_min) × scale.
  uint32_t sensor_counts_low = 0, sensor_counts_high = 0;
  float sensor_min_pa = 0, sensor_counts_min = 0, sensor_pa_per_count = 0;
  /// Already intersected with the hard ceiling and the regulator's command range.
  float limit_min_pa = 0, limit_max_pa = 0;
  float safe_pa = 0;
  float max_step_pa = 0;  ///< slew per tick; the largest float when none
  /// Slew per tick once shaping fell back: the line's own, or kFallbackSlewPaPerS's.
  float fallback_max_step_pa = 0;
  float regulator_min_pa = 0;
  float pump_below_pa = 0;  ///< commands below this need the vacuum pump (lowest float: never)
  /// DAC scaling as one multiply-add: code + ½ = command × counts_per_pa + counts_at_zero,
  /// truncated. The step's commands lie within the limits, so within the command range; CountsFor
  /// also holds other pressures to [rounded_low, rounded_high] (0 % and 100 % of the signal, ½
  /// added), the DAC's ends.
  float counts_per_pa = 0, counts_at_zero = 0;
  float rounded_low = 0, rounded_high = 0;
  uint32_t safe_counts = 0, zero_counts = 0;  ///< DAC codes for safe_pa and for 0 Pa
  float kp = 0, ki_dt = 0;                    ///< ki already multiplied by the tick period
  float authority_pa = 0, dead_band_pa = 0;
  float model_alpha = 1;  ///< regulator-model lag per tick
  /// The regulator model's dead time in ticks (at most kMaxDeadTicks - 1).
  uint8_t delay_ticks = 0;
  /// Step shaping, on when the chamber's lag is known, an overdrive allowed and a sensor reads
  /// the outlet: the command that brings the regulator model in one tick to the target led by
  /// the chamber's lead, as shape_target × target + shape_chamber × chamber estimate +
  /// shape_regulator × regulator model + (target − chamber) × lead_gain / (O + C + 2 p_atm)
  /// (line_step.h), the chamber estimated from the outlet's reading through the tube's law
  /// (tube_k_dt: k × the tick, 1/Pa), how far beyond the target the command may go, and how
  /// many ticks the trim holds after the command last left the target (dead time + settling).
  bool shaping = false;
  float shape_target = 1, shape_chamber = 0, shape_regulator = 0;
  float tube_k_dt = 0, lead_gain = 0;
  float overdrive_pa = 0;
  uint16_t shape_hold_ticks = 0;
  Correction correction{};  ///< the regulator correction, with its lookup tables
  /// Venting (last: the fields the step reads on every tick keep their offsets): this line's bit in
  /// the board's vent outputs when it may open its dump valve (a shaped line whose limits hold
  /// atmosphere), else 0. A target below the regulator's minimum opens it: the regulator's exhaust
  /// closes in proportion to the pressure left (its pilot stops at 0), the dump valve takes the
  /// outlet to atmosphere and no further.
  uint32_t vent_bit = 0;
  /// A shaped step's command held at the line's upper limit where that is atmosphere (a vacuum
  /// line's): vent_bit, the dump valve open with the regulator's exhaust, and 1 (else 0), the
  /// regulator model taken from the outlet's reading (line_step.h).
  uint32_t vent_high_bit = 0;
  float model_from_outlet_high = 0;
};

LineParams MakeLineParams(const protocol::ConfigureLine& line, uint32_t tick_us);

struct LineState {
  /// The slew per tick the line runs with: the line's own, its fallback's once shaping fell back
  /// (ResetLineState sets it).
  float max_step_pa = 0;
  float slewed_pa = 0;  ///< setpoint after the slew limiter
  float integrator_pa = 0;
  float reference_pa = 0;  ///< regulator-model output: where the pressure should be now
  /// The commands of the last kMaxDeadTicks ticks, a ring; the next one goes to delay_index.
  std::array<float, kMaxDeadTicks> delay{};
  uint8_t delay_index = 0;
  bool rising = true;  ///< direction for the correction branch, kept while steady (lines with one)
  uint16_t trim_hold = 0;  ///< shaping: ticks left before the trim acts again
  /// Shaping: where the models of the regulator's output and of the chamber say they are, the
  /// dead time left out (the regulator sees the commands in the same order, only later).
  float regulator_pa = 0, chamber_pa = 0;
  float wanted_pa = 0;  ///< shaping: what the regulator was last asked for (slewed or shaped)
  float steady_pa = 0;  ///< shaping: the setpoint the line has settled on; none during a step
  /// Shaping: the outlet's last reading in a hold, or as one ended (where it was as the next
  /// overdrive began: the overdrive's ticks read nothing), and that reading kept as the overdrive
  /// ends, for the watch through the hold after it.
  float hold_reading_pa = 0, start_reading_pa = 0;
  /// Shaping fell back: a step's outlet went beyond its target and the model (kShapeFallbackPa),
  /// so the line's steps are unshaped until it is configured again (ResetLineState keeps it, the
  /// board's Diagnostics says it).
  bool shaping_fell_back = false;
  /// Shaping: the side of the target the last overdrive pushed toward (the watch's direction).
  bool overdrive_up = false;
  /// How far beyond the target a shaped step's command may go: the line's overdrive, none once
  /// shaping fell back (its steps then end where they start: no extra test on the step's path).
  float overdrive_pa = 0;
};

/// Resets the state to hold `pa` steadily (after configuration, or leaving the safe state).
void ResetLineState(const LineParams& p, LineState& s, float pa);

/// What the line's pressure sensor read this tick (the board's sensing stage fills it).
struct LineReading {
  bool valid = false;  ///< the line's sensor read a pressure (never set without a sensor)
  /// line_status::kSensorFault when the line has a sensor whose reading is no pressure: the
  /// status reports it in and out of the safe state.
  uint8_t status = 0;
  float pa = 0;
};

struct LineOutput {
  float command_pa = 0;  ///< pressure the regulator is commanded to (after trim and clamp)
  uint8_t status = 0;    ///< protocol::line_status bits
};

/// One tick of one line outside the safe state: returns the DAC code to write and fills every
/// field of `out`. The trim closes the loop while `reading` is valid. ORs the line's vent_bit
/// into `*vents` (where given) while the line vents.
uint32_t StepLine(const LineParams& p, LineState& s, float setpoint_pa, const LineReading& reading,
                  LineOutput& out, uint32_t* vents = nullptr);

/// One tick of one line in the safe state: the safe value at once, bypassing slew, trim and
/// model, with the state reset to hold it. Returns the safe DAC code; fills every field of `out`.
uint32_t HoldLineSafe(const LineParams& p, LineState& s, const LineReading& reading,
                      LineOutput& out);

/// DAC code for a commanded pressure (clamped to the DAC's range).
uint32_t CountsFor(const LineParams& p, float command_pa);

}  // namespace palpa::core
