// The board: start-up, the main loop pass, applying a configuration, the configuration check.
#include "palpa/core/board.h"

#include <cstring>

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
  config_saved_ = !config_is_default_;
  config_unsaved_ = false;
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
  for (uint8_t i = 0; i < kMaxLines; ++i) {
    line_owner_[i] = FingerOfLine(live_, i);
    if (i < live_.line_count) {
      const LineParams& p = line_params_[i] = MakeLineParams(live_.lines[i], kTickUs);
      ResetLineState(p, line_state_[i], p.safe_pa);
      setpoint_pa_[i] = p.safe_pa;
      dac_codes_[i] = p.safe_counts;
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

void Board::EndSession() {
  Hold();
  safe_ = true;  // Critical for safety: as for EStop, the next tick's outputs are safe codes
  session_.End();
  if (io_.update != nullptr) io_.update->LeaveUpdateMode();
}

void Board::HeardFromHost(uint64_t now_us) {
  session_.Heard();
  last_host_frame_us_ = now_us;
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
