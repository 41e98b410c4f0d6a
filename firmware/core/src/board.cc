// The control tick: inputs → supervisor → fingers → lines → outputs → telemetry.
#include "palpa/core/board.h"

#include <cstring>

#include "line_step.h"
#include "palpa/core/update_engine.h"
#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

using protocol::Fault;
using protocol::kMaxLines;
using protocol::kNoLine;

uint32_t MemoryCrc(const BoardConfig& config) {
  return protocol::Crc32(reinterpret_cast<const uint8_t*>(&config), sizeof(config));
}

constexpr uint32_t kCrcSliceBytes = 512;  // per tick: a 6 KB configuration every ~12 ticks

}  // namespace

Board::Board(const BoardConfig& factory, BoardIo io, BoardIdentity identity)
    : factory_(factory),
      io_(io),
      identity_(identity),
      store_(io.flash, io.flash_config_base),
      session_(identity.boot_nonce),
      supply_pulse_(io.supply_enable),
      dump_pulse_(io.dump_enable) {}

void Board::Start() {
  // Critical for safety: every output to its safe code before anything else happens.
  const uint64_t now = io_.clock.NowMicros();
  std::memset(&live_, 0, sizeof(live_));  // padding too: the integrity CRC covers raw memory
  config_is_default_ = store_.Load(factory_, live_) == ConfigStore::Source::kFactory;
  if (!config_is_default_ && !DacMatches(live_, nullptr)) {  // saved for other hardware
    std::memcpy(&live_, &factory_, sizeof(live_));
    config_is_default_ = true;
  }
  ApplyLive(now);
  WriteOutputs();
  switch (identity_.reset_cause) {
    case protocol::ResetCause::kWatchdog:
    case protocol::ResetCause::kBrownOut:
    case protocol::ResetCause::kFaultHandler:
      LatchFault(supervisor_, Fault::kUnexpectedReset, now,
                 static_cast<int32_t>(identity_.reset_cause));
      break;
    default:
      break;
  }
  // The first deadline is when the board is ready: loading and applying the configuration above
  // takes ≈ 4 ms at 25 MHz, which would otherwise count as late ticks on every start.
  pacer_.Start(io_.clock.NowMicros());
}

bool Board::DacMatches(const BoardConfig& config, ConfigError* error) const {
  for (uint8_t i = 0; i < config.line_count; ++i) {
    const hal::AnalogOutputSpec spec = io_.dac.spec(i);
    if (config.lines[i].dac_bits != spec.bits || config.lines[i].dac_signal != spec.range) {
      if (error != nullptr)
        *error = {protocol::ConfigSection::kLine, i,
                  "DAC resolution or signal range differs from the board's DAC"};
      return false;
    }
  }
  return true;
}

bool Board::Step() {
  const uint64_t now = io_.clock.NowMicros();
  bool ticked = false;
  if (pacer_.Due(now)) {
    Tick(now);
    ticked = true;
  }
  Poll(io_.clock.NowMicros());
  return ticked;
}

void Board::ApplyLive(uint64_t now_us) {
  settings_ = MakeSupervisorSettings(live_.board);
  supervisor_input_ = SupervisorInput{};
  // Critical for safety: a channel the new configuration no longer has (a FactoryReset after a
  // host added a line) would keep commanding what its old line last asked for, since the tick
  // writes configured lines only. It is parked at its old line's safe code, retried each tick
  // until the write succeeds; nothing writes it after that.
  for (uint8_t i = live_.line_count; i < driven_lines_; ++i) unparked_channels_ |= 1u << i;
  unparked_channels_ &= ~((1u << live_.line_count) - 1u);  // configured again: the tick writes it
  driven_lines_ = live_.line_count;
  ParkDroppedChannels();
  const float tolerance = static_cast<float>(live_.board.sensor_tolerance_pa);
  vacuum_line_count_ = 0;
  for (uint8_t i = 0; i < kMaxLines; ++i) {
    line_owner_[i] = FingerOfLine(live_, i);
    if (i < live_.line_count) {
      const LineParams& p = line_params_[i] = MakeLineParams(live_.lines[i], kTickUs);
      ResetLineState(p, line_state_[i], p.safe_pa);
      setpoint_pa_[i] = p.safe_pa;
      dac_codes_[i] = p.safe_counts;
      if (live_.lines[i].kind == protocol::LineKind::kVacuum)
        vacuum_lines_[vacuum_line_count_++] = i;
      line_out_[i] =
          LineOutput{p.safe_pa, protocol::line_status::kSafe | protocol::line_status::kOpenLoop};
      // What the supervisor sees of a line that the configuration fixes, once per configuration.
      LineObservation& o = supervisor_input_.lines[i];
      o.configured = true;
      o.has_sensor = p.has_sensor && io_.adc != nullptr;
      // A sensor with no ADC to read it never gives a pressure: open loop, reported as such.
      o.reading.status = p.has_sensor && !o.has_sensor ? protocol::line_status::kSensorFault : 0;
      o.alarm_below_pa = p.limit_min_pa - tolerance;
      o.alarm_above_pa = p.limit_max_pa + tolerance;
    }
  }
  for (uint8_t f = 0; f < live_.finger_count; ++f) {
    const protocol::ConfigureFinger& finger = live_.fingers[f];
    const bool jamming = finger.kind == protocol::FingerKind::kJamming;
    const protocol::ConfigureLine& driven = live_.lines[jamming ? finger.line_b : finger.line_a];
    const float drive_limit =
        static_cast<float>(jamming ? -driven.limit_min_pa : driven.limit_max_pa);
    finger_params_[f] = MakeFingerParams(finger, drive_limit);
    finger_state_[f].target = 0;
  }
  config_crc_ = ConfigCrc(live_);
  config_memory_crc_ = MemoryCrc(live_);
  check_offset_ = 0;
  check_crc_ = 0;
  next_check_us_ = now_us;
  config_intact_ = true;
  Hold();
}

void Board::Hold() {
  released_ = false;
  for (FingerState& f : finger_state_) RequireHoming(f);
  RefreshLineFlags();
}

void Board::RefreshLineFlags() {
  line_flags_ = {};
  for (uint8_t f = 0; f < live_.finger_count; ++f) {
    if (finger_state_[f].mode != protocol::FingerMode::kRaw) continue;
    const FingerParams& p = finger_params_[f];
    line_flags_[p.line_a] = protocol::line_status::kRaw;
    if (p.line_b != kNoLine) line_flags_[p.line_b] = protocol::line_status::kRaw;
  }
}

void Board::Tick(uint64_t now_us) {
  pacer_.BeginTick(now_us);
  SupervisorInput& in = supervisor_input_;
  ReadInputs(now_us, in);
  CheckConfigIntegrity(now_us);
  in.config_intact = config_intact_;
  if (estop_requested_) {
    LatchFault(supervisor_, Fault::kEStopCommand, now_us, 0);
    estop_requested_ = false;
  }
  ObserveSlowSlot();
  const uint32_t newly = Supervise(settings_, supervisor_, in);
  const bool was_safe = safe_;
  // Update mode keeps every line safe from Enter until the reboot or the next session (DESIGN §9).
  const bool updating =
      identity_.recovery || (io_.update != nullptr && io_.update->in_update_mode());
  safe_ = supervisor_.latched != 0 || !released_ || updating;
  if (safe_ && !was_safe) Hold();

  ComputeSetpoints(now_us);
  StepLines();
  WriteOutputs();
  SampleTelemetry(now_us, newly != 0);
  pacer_.EndTick(io_.clock.NowMicros());
}

void Board::ReadInputs(uint64_t now_us, SupervisorInput& in) {
  in.now_us = now_us;
  in.session_open = session_.open();
  in.last_host_frame_us = last_host_frame_us_;
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
    StepFinger(*p, *s, seen.valid ? seen.pa : line_state_[p->driven_line].reference_pa, tick);
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
  for (; p != end; ++p, ++state, ++out, ++o, ++setpoint, ++flags, ++code) {
    *code = safe ? HoldLineSafe(*p, *state, o->reading, *out)
                 : StepLineInline(*p, *state, *setpoint, o->reading, *out);
    out->status |= *flags;
  }
  // The pump follows on the next tick's supervision: needed while a vacuum line commands more
  // vacuum than its regulator's minimum.
  bool vacuum = false;
  for (uint8_t k = 0; k < vacuum_line_count_; ++k) {
    const uint8_t i = vacuum_lines_[k];
    vacuum |= line_out_[i].command_pa < line_params_[i].pump_below_pa;
  }
  supervisor_input_.vacuum_demand = vacuum;
}

void Board::WriteOutputs() {
  // The supervisor judges a failed write on the next tick.
  uint8_t failed = io_.dac.WriteAll(dac_codes_.data(), live_.line_count);
  if (unparked_channels_ != 0) {
    const uint8_t channel = ParkDroppedChannels();
    if (failed == hal::AnalogOutput::kAllWritten) failed = channel;
  }
  supervisor_input_.failed_output = failed == hal::AnalogOutput::kAllWritten ? kNoLine : failed;
  // Critical for safety: valves and pump are held only while the board is not safe.
  supply_pulse_.Tick(!safe_);
  dump_pulse_.Tick(!safe_);
  io_.pump_enable.Set(!safe_ && supervisor_.pump_on);
}

uint8_t Board::ParkDroppedChannels() {
  uint8_t failed = kNoLine;
  for (uint8_t i = 0; i < kMaxLines; ++i) {
    if ((unparked_channels_ & (1u << i)) == 0) continue;
    if (io_.dac.Write(i, line_params_[i].safe_counts) == protocol::Status::kOk) {
      unparked_channels_ &= ~(1u << i);
    } else if (failed == kNoLine) {
      failed = i;
    }
  }
  return failed;
}

void Board::CheckConfigIntegrity(uint64_t now_us) {
  if (check_offset_ == 0) {  // a pass starts every check period and takes a few ticks
    if (now_us < next_check_us_) return;
    next_check_us_ = now_us + static_cast<uint64_t>(live_.board.config_check_period_ms) * 1000;
  }
  const auto* bytes = reinterpret_cast<const uint8_t*>(&live_);
  const uint32_t remaining = static_cast<uint32_t>(sizeof(live_)) - check_offset_;
  const uint32_t slice = remaining < kCrcSliceBytes ? remaining : kCrcSliceBytes;
  check_crc_ = protocol::Crc32Update(check_crc_, bytes + check_offset_, slice);
  check_offset_ += slice;
  if (check_offset_ < sizeof(live_)) return;
  config_intact_ = check_crc_ == config_memory_crc_;
  check_offset_ = 0;
  check_crc_ = 0;
}

}  // namespace palpa::core
