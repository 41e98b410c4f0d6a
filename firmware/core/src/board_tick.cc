// The control tick: inputs → supervisor → fingers → lines → outputs (telemetry: board_reports.cc).
#include "finger_step.h"
#include "line_step.h"
#include "palpa/core/board.h"
#include "palpa/core/update_engine.h"

namespace palpa::core {

using protocol::Fault;
using protocol::kMaxLines;
using protocol::kNoLine;

void Board::Tick(uint64_t now_us) {
  pacer_.BeginTick(now_us);
  SupervisorInput& in = supervisor_input_;
  ReadInputs(now_us, in);
  CheckConfigIntegrity(now_us);
  in.config_intact = config_intact_;
  // An EStop latched its fault when it arrived; this tick's telemetry reports it.
  const bool estop_arrived = estop_requested_;
  estop_requested_ = false;
  ObserveSlowSlot();
  const uint32_t newly = Supervise(settings_, supervisor_, in);
  // Silence ends the session (the fault, if any, is latched above), once this tick's telemetry
  // has reported it; the outputs are safe this tick already. The bootloader's recovery mode,
  // which never actuates, keeps its session for a flasher that pauses.
  const bool silent = supervisor_.host_silent && !identity_.recovery;
  if (silent) Hold();
  const bool was_safe = safe_;
  // Update mode keeps every line safe from Enter until the reboot or the next session (DESIGN §9).
  const bool updating =
      identity_.recovery || (io_.update != nullptr && io_.update->in_update_mode());
  safe_ = supervisor_.latched != 0 || !released_ || updating;
  if (safe_ && !was_safe) Hold();

  ComputeSetpoints(now_us);
  StepLines();
  WriteOutputs();
  SampleTelemetry(now_us, newly != 0 || estop_arrived);
  if (silent) EndSession();
  pacer_.EndTick(io_.clock.NowMicros());
}

void Board::ReadInputs(uint64_t now_us, SupervisorInput& in) {
  in.now_us = now_us;
  in.session_open = session_.open();
  in.last_host_frame_us = last_host_frame_us_;
  in.actuating = released_;
  in.estop_pin = io_.estop != nullptr && io_.estop->Read();
  in.safe = safe_;
  if (io_.adc == nullptr) return;
  uint32_t scan[kMaxLines];  // one scan of every configured line's channel
  const uint8_t count = live_.line_count;
  io_.adc->ReadAll(scan, count);
  LineObservation* o = in.lines.data();
  const LineParams* p = line_params_.data();
  ReadingSummary summary;
  for (uint8_t i = 0; i < count; ++i, ++o, ++p) {
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
    NoteReading(summary, i, reading, *o);
  }
  in.readings = summary;
}

void Board::ObserveSlowSlot() {
  const uint8_t slot = SlowSlot(supervisor_);
  if (slot >= live_.line_count) return;
  LineObservation& o = supervisor_input_.lines[slot];
  o.reference_pa = line_state_[slot].reference_pa;
  o.setpoint_pa = line_state_[slot].slewed_pa;
  o.closed_loop = (line_out_[slot].status & protocol::line_status::kOpenLoop) == 0;
}

void Board::ComputeSetpoints(uint64_t now_us) {
  if (safe_) return;  // the lines hold their safe values; fingers re-home when it ends
  const FingerTick tick{now_us, static_cast<uint32_t>(live_.board.home_dwell_ms) * 1000,
                        setpoint_pa_.data(), line_flags_.data()};
  const FingerParams* p = finger_params_.data();
  const FingerParams* const end = p + live_.finger_count;
  FingerState* s = finger_state_.data();
  for (; p != end; ++p, ++s) {
    if (s->mode != protocol::FingerMode::kTarget) continue;  // raw: the host drives the lines
    // The compensator's memory follows what the driven line applied: the reading, or where the
    // regulator model has the pressure when there is no reading.
    const LineReading& seen = supervisor_input_.lines[p->driven_line].reading;
    StepFingerInline(*p, *s, seen.valid ? seen.pa : line_state_[p->driven_line].reference_pa, tick);
  }
}

void Board::StepLines() {
  // Walked by pointer, with what the loop reads of the board in locals: the stores through the
  // line pointers could alias the board's members, so they would be reloaded every line.
  const LineParams* p = line_params_.data();
  const LineParams* const end = p + live_.line_count;
  LineState* state = line_state_.data();
  LineOutput* out = line_out_.data();
  const LineObservation* o = supervisor_input_.lines.data();
  const float* setpoint = setpoint_pa_.data();
  const uint8_t* flags = line_flags_.data();
  uint32_t* code = dac_codes_.data();
  const bool safe = safe_;
  bool vacuum = false;  // a vacuum line commands more than its regulator's minimum: the pump runs
  for (; p != end; ++p, ++state, ++out, ++o, ++setpoint, ++flags, ++code) {
    *code = safe ? HoldLineSafe(*p, *state, o->reading, *out)
                 : StepLineInline(*p, *state, *setpoint, o->reading, *out);
    out->status |= *flags;
    vacuum |= out->command_pa < p->pump_below_pa;
  }
  supervisor_input_.vacuum_demand = vacuum;  // the pump follows on the next tick's supervision
}

void Board::WriteOutputs() {
  // The supervisor judges a failed write on the next tick.
  uint8_t failed = io_.dac.WriteAll(dac_codes_.data(), live_.line_count);
  if (failed == hal::AnalogOutput::kAllWritten) failed = kNoLine;
  if (unparked_channels_ != 0) {
    const uint8_t channel = ParkDroppedChannels();
    if (failed == kNoLine) failed = channel;
  }
  supervisor_input_.failed_output = failed;
  // Critical for safety: valves and pump are held only while the board is not safe.
  supply_pulse_.Tick(!safe_);
  dump_pulse_.Tick(!safe_);
  io_.pump_enable.Set(!safe_ && supervisor_.pump_on);
}

}  // namespace palpa::core
