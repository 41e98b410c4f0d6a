// The board's lines: a configuration applied, dropped channels parked, raw setpoints checked and
// taken (the tick's stages are in board_lines_tick.cc).
#include "palpa/core/internal/board_lines.h"
#include "palpa/core/internal/board_fingers.h"

namespace palpa::core {

using protocol::kMaxLines;

void BoardLines::Apply(const BoardConfig& live, uint32_t tick_us, bool has_adc, SupervisorInput& in,
                       hal::AnalogOutput& dac) {
  // Critical for safety: a channel the new configuration no longer has (a FactoryReset after a
  // host added a line) would keep commanding what its old line last asked for, since the tick
  // writes configured lines only. It is parked at its old line's safe code, retried each tick
  // until the write succeeds; nothing writes it after that.
  for (uint8_t i = live.line_count; i < count_; ++i) unparked_channels_ |= 1u << i;
  unparked_channels_ &= ~((1u << live.line_count) - 1u);  // configured again: the tick writes it
  count_ = live.line_count;
  ParkDroppedChannels(dac);
  const float tolerance = static_cast<float>(live.board.sensor_tolerance_pa);
  corrected_ = false;
  for (uint8_t i = 0; i < live.line_count; ++i) {
    // Shaping estimates the chamber from the outlet's reading: none without an ADC to read it.
    protocol::ConfigureLine line = live.lines[i];
    if (!has_adc) line.chamber_tau_us = 0;
    const LineParams& p = params_[i] = MakeLineParams(line, tick_us);
    corrected_ = corrected_ || p.correction.count >= 2;
    state_[i].shaping_fell_back = false;  // a new chamber model gets its chance
    ResetLineState(p, state_[i], p.safe_pa);
    setpoint_pa_[i] = p.safe_pa;
    dac_codes_[i] = p.safe_counts;
    out_[i] =
        LineOutput{p.safe_pa, protocol::line_status::kSafe | protocol::line_status::kOpenLoop};
    // What the supervisor sees of a line that the configuration fixes, once per configuration.
    LineObservation& o = in.lines[i];
    o.configured = true;
    o.has_sensor = p.has_sensor && has_adc;
    // A sensor with no ADC to read it never gives a pressure: open loop, reported as such.
    o.reading.status = p.has_sensor && !o.has_sensor ? protocol::line_status::kSensorFault : 0;
    o.alarm_below_pa = p.limit_min_pa - tolerance;
    o.alarm_above_pa = p.limit_max_pa + tolerance;
  }
}

uint8_t BoardLines::ParkDroppedChannels(hal::AnalogOutput& dac) {
  uint8_t failed = protocol::kNoLine;
  for (uint8_t i = 0; i < kMaxLines; ++i) {
    if ((unparked_channels_ & (1u << i)) == 0) continue;
    if (dac.Write(i, params_[i].safe_counts) == protocol::Status::kOk) {
      unparked_channels_ &= ~(1u << i);
    } else if (failed == protocol::kNoLine) {
      failed = i;
    }
  }
  return failed;
}

Status BoardLines::Accept(const protocol::SetLineSetpoints& m, const BoardFingers& fingers,
                          uint32_t& detail) {
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    const protocol::LineSetpoint& e = m.entries[i];
    detail = i;
    if (e.line >= count_) return Status::kNotFound;
    if (!fingers.TakesRawSetpoints(e.line)) return Status::kWrongMode;
    const LineParams& p = params_[e.line];
    const float v = static_cast<float>(e.setpoint_pa);
    if (v < p.limit_min_pa || v > p.limit_max_pa) return Status::kOutOfRange;
  }
  detail = 0;
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    setpoint_pa_[m.entries[i].line] = static_cast<float>(m.entries[i].setpoint_pa);
  }
  return Status::kOk;
}

}  // namespace palpa::core
