// Internal to firmware/core: the board's lines — what each is configured as, its pipeline state,
// its last output and DAC code, what it steps towards, and the status bits its finger adds. The
// sensing and line stages of the tick, and raw setpoints from the host, go through here.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/line_pipeline.h"
#include "palpa/core/supervisor.h"
#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/protocol/messages_stream.h"

namespace palpa::core {

class BoardFingers;

class BoardLines {
 public:
  /// A new live configuration: every line at its safe value, what the supervisor sees of each
  /// line that the configuration fixes written into `in`, and the channels it dropped parked at
  /// their old line's safe code.
  void Apply(const BoardConfig& live, uint32_t tick_us, bool has_adc, SupervisorInput& in,
             hal::AnalogOutput& dac);

  /// The sensing stage: one scan of the configured lines' channels, converted to pressures.
  void Sense(hal::AnalogInput& adc, SupervisorInput& in);
  /// The line stage: every line one step (or held safe), DAC codes for WriteDac; notes in `in`
  /// whether a vacuum line needs the pump, and which lines vent (vents()). Out of line, so
  /// instruction counts can bracket the line stage (its steps are inlined).
  [[gnu::noinline]] void Step(bool safe, SupervisorInput& in);
  /// Writes this tick's codes, and the safe code of any dropped channel not parked yet; returns
  /// the first channel whose write failed, or kNoLine.
  uint8_t WriteDac(hal::AnalogOutput& dac) {
    uint8_t failed = dac.WriteAll(dac_codes_.data(), count_);
    if (failed == hal::AnalogOutput::kAllWritten) failed = protocol::kNoLine;
    if (unparked_channels_ != 0) {
      const uint8_t channel = ParkDroppedChannels(dac);
      if (failed == protocol::kNoLine) failed = channel;
    }
    return failed;
  }
  /// The slow monitors' view of `line`: where the last tick left it.
  void Observe(uint8_t line, LineObservation& o) const {
    o.reference_pa = state_[line].reference_pa;
    o.setpoint_pa = state_[line].slewed_pa;
    o.closed_loop = (out_[line].status & protocol::line_status::kOpenLoop) == 0;
  }

  /// Raw setpoints from the host: each entry names a configured line whose finger (if any) is in
  /// raw mode, within the line's limits. kNotFound / kWrongMode / kOutOfRange with the entry's
  /// index in `detail`; nothing is applied unless every entry passes.
  Status Accept(const protocol::SetLineSetpoints& m, const BoardFingers& fingers, uint32_t& detail);
  /// A finger going raw: its line steps towards where it is now, until the host says otherwise.
  void HoldWhereItIs(uint8_t line) { setpoint_pa_[line] = state_[line].slewed_pa; }

  /// The lines whose dump valves this tick opens, one bit each (bit i: line i): the lines that
  /// vent toward atmosphere, or every one while the board is safe (their safe default).
  uint32_t vents() const { return vents_; }
  static constexpr uint32_t kAllVents = (1u << protocol::kMaxLines) - 1u;

  uint8_t count() const { return count_; }
  const LineParams& params(uint8_t line) const { return params_[line]; }
  const LineState& state(uint8_t line) const { return state_[line]; }
  const LineOutput& output(uint8_t line) const { return out_[line]; }
  uint32_t dac_code(uint8_t line) const { return dac_codes_[line]; }
  const LineState* states() const { return state_.data(); }
  /// Where the fingers in target mode write their lines' setpoints and status bits each tick.
  float* setpoints() { return setpoint_pa_.data(); }
  uint8_t* flags() { return flags_.data(); }

 private:
  uint8_t ParkDroppedChannels(hal::AnalogOutput& dac);

  uint8_t count_ = 0;  ///< the live configuration's lines: DAC channels the tick writes
  /// A line has a regulator correction: the line stage runs the loop that looks corrections up
  /// (the lookup holds registers the loop without it keeps its pointers in).
  bool corrected_ = false;
  std::array<LineParams, protocol::kMaxLines> params_{};
  std::array<LineState, protocol::kMaxLines> state_{};
  std::array<LineOutput, protocol::kMaxLines> out_{};
  /// What the DAC is given each tick, one scan of the configured lines (safe codes until a tick).
  std::array<uint32_t, protocol::kMaxLines> dac_codes_{};
  /// What each line steps towards: the host's raw setpoint, or what its finger in target mode
  /// wrote this tick (the host cannot send raw setpoints for such a line).
  std::array<float, protocol::kMaxLines> setpoint_pa_{};
  /// Status bits a line's finger adds to it: kRaw while the finger is in raw mode, kSaturated
  /// while its compensator is clamped (written by each step; cleared when the board goes safe).
  std::array<uint8_t, protocol::kMaxLines> flags_{};
  uint32_t unparked_channels_ = 0;  ///< dropped channels whose safe code is not written yet
  uint32_t vents_ = kAllVents;
};

}  // namespace palpa::core
