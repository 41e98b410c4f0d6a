// The tick's sensing and line stages over the board's lines (at -O2, with the line step inlined).
#include "line_step.h"
#include "palpa/core/internal/board_lines.h"

namespace palpa::core {

using protocol::kMaxLines;

namespace {

/// The stepping loop, in two copies: with the correction's lookup, and without it for boards
/// whose lines have none (the lookup's registers cost the loop a spill on every line). Returns
/// whether a vacuum line needs the pump.
template <bool kCorrection>
[[gnu::always_inline]] inline bool StepLines(const LineParams* p, const LineParams* const end,
                                             LineState* state, LineOutput* out,
                                             const LineObservation* o, const float* setpoint,
                                             const uint8_t* flags, uint32_t* code,
                                             uint32_t& vents) {
  bool vacuum = false;
  for (; p != end; ++p, ++state, ++out, ++o, ++setpoint, ++flags, ++code) {
    *code = StepLineEither<kCorrection>(*p, *state, *setpoint, o->reading, *out, vents, *flags);
    vacuum |= out->command_pa < p->pump_below_pa;
  }
  return vacuum;
}

}  // namespace

void BoardLines::Sense(hal::AnalogInput& adc, SupervisorInput& in) {
  uint32_t scan[kMaxLines];  // one scan of every configured line's channel
  const uint8_t count = count_;
  adc.ReadAll(scan, count);
  LineObservation* o = in.lines.data();
  const LineParams* p = params_.data();
  ReadingSummary summary;
  // A word-sized index: a uint8_t one is zero-extended again on every pass (NoteReading keeps
  // the line's number in a byte; it is below kMaxLines).
  for (uint32_t i = 0; i < count; ++i, ++o, ++p) {
    if (!o->has_sensor) continue;
    const uint32_t counts = scan[i];
    // Readings outside the sensor's output span (open or shorted wire) are not pressures; nor is
    // a failed conversion (kConversionFailed lies above every span).
    LineReading reading;
    reading.valid = counts >= p->sensor_counts_low && counts <= p->sensor_counts_high;
    reading.status = reading.valid ? 0 : protocol::line_status::kSensorFault;
    reading.pa = reading.valid
                     ? p->sensor_min_pa + (static_cast<float>(counts) - p->sensor_counts_min) *
                                              p->sensor_pa_per_count
                     : o->reading.pa;  // an invalid reading keeps the last pressure
    o->reading = reading;
    o->raw_counts = counts;
    NoteReading(summary, static_cast<uint8_t>(i), reading, *o);
  }
  in.readings = summary;
}

void BoardLines::Step(bool safe, SupervisorInput& in) {
  // Walked by pointer, with what the loop reads in locals: the stores through the line pointers
  // could alias the members, so they would be reloaded every line.
  const LineParams* p = params_.data();
  const LineParams* const end = p + count_;
  LineState* state = state_.data();
  LineOutput* out = out_.data();
  const LineObservation* o = in.lines.data();
  const float* setpoint = setpoint_pa_.data();
  const uint8_t* flags = flags_.data();
  uint32_t* code = dac_codes_.data();
  bool vacuum = false;  // a vacuum line commands more than its regulator's minimum: the pump runs
  // Every line's valve open while safe (its default); else the lines' steps say which. Kept in
  // memory: the rare step that vents ORs its bit in, the loop holds no register for it.
  uint32_t& vents = vents_;
  // Two loops rather than a test of `safe` on every line (it did not stay in a register).
  if (safe) {
    vents = kAllVents;
    for (; p != end; ++p, ++state, ++out, ++o, ++flags, ++code) {
      *code = HoldLineSafe(*p, *state, o->reading, *out);
      out->status |= *flags;
      vacuum |= out->command_pa < p->pump_below_pa;
    }
  } else {
    vents = 0u;
    vacuum = corrected_ ? StepLines<true>(p, end, state, out, o, setpoint, flags, code, vents)
                        : StepLines<false>(p, end, state, out, o, setpoint, flags, code, vents);
  }
  in.vacuum_demand = vacuum;  // the pump follows on the next tick's supervision
}

}  // namespace palpa::core
