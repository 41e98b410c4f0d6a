// The board's brain: configuration, session, supervisor, fingers and lines, run from a loop shell
// that calls Step(). Talks to hardware only through hal interfaces.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/config_store.h"
#include "palpa/core/finger.h"
#include "palpa/core/line_pipeline.h"
#include "palpa/core/supervisor.h"
#include "palpa/core/tick_pacer.h"
#include "palpa/core/tx_queue.h"
#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/flash.h"
#include "palpa/protocol/framing.h"
#include "palpa/protocol/session.h"

namespace palpa::core {

/// Hardware the core drives. Line i uses DAC channel i and ADC channel i.
struct BoardIo {
  hal::Clock& clock;
  hal::AnalogOutput& dac;
  hal::AnalogInput* adc;              ///< nullptr: no sensors fitted
  hal::DigitalOutput& supply_enable;  ///< pulsing enable of the normally-closed supply shut-off
  hal::DigitalOutput& dump_enable;    ///< pulsing enable of the normally-open dump valve
  hal::DigitalOutput& pump_enable;
  hal::DigitalInput* estop;  ///< nullptr: no E-stop input; high = asserted
  hal::ByteLink& link;
  hal::Flash* flash;  ///< nullptr: nothing persists
  uint32_t flash_config_base = 0;
  class UpdateEngine* update = nullptr;  ///< nullptr: the board cannot be updated over the link
};

struct BoardIdentity {
  protocol::BoardKind kind = protocol::BoardKind::kSim;
  uint32_t board_id = 0;
  uint8_t firmware_major = 0, firmware_minor = 1, firmware_patch = 0;
  bool plant_simulated = false;
  float time_scale = 1.0f;
  protocol::ResetCause reset_cause = protocol::ResetCause::kPowerOn;
  uint32_t boot_nonce = 0;
  uint32_t boot_count = 0;
  uint8_t active_slot = 0;
  uint32_t rollback_counter = 0;
  uint16_t rx_buffer_bytes = 1024;
  /// No valid image: the bootloader's recovery mode — the bootstrap set only, every line safe.
  bool recovery = false;
};

class Board {
 public:
  static constexpr uint32_t kTickUs = 1000;

  Board(const BoardConfig& factory, BoardIo io, BoardIdentity identity);

  /// Outputs safe, configuration loaded (flash or factory), unexpected resets latched.
  void Start();
  /// One pass of the main loop: a control tick when due, then link input and output.
  /// Returns true when a tick ran (the shell kicks the watchdog only then).
  bool Step();

  // Views for tests, the simulator and diagnostics.
  const BoardConfig& config() const { return live_; }
  uint32_t latched_faults() const { return supervisor_.latched; }
  uint32_t active_conditions() const { return supervisor_.active; }
  bool safe() const { return safe_; }
  const LineOutput& line_output(uint8_t line) const { return line_out_[line]; }
  uint32_t dac_code(uint8_t line) const { return dac_codes_[line]; }
  const LineState& line_state(uint8_t line) const { return line_state_[line]; }
  const TickStats& tick_stats() const { return pacer_.stats(); }
  const protocol::FramingCounters& rx_counters() const { return decoder_.counters(); }
  const TxQueue& tx() const { return tx_; }
  bool config_is_default() const { return config_is_default_; }
  bool config_saved() const { return config_saved_; }
  bool config_unsaved() const { return config_unsaved_; }
  /// When the session's host last sent a fresh frame (Hello, a newer heartbeat, an applied
  /// command or stream frame): what the host-silence timer counts from.
  uint64_t last_host_frame_us() const { return last_host_frame_us_; }
  bool session_open() const { return session_.open(); }
  /// The open session's identity: its Hello's nonce, which its frames carry.
  uint32_t session_nonce() const { return session_.host_nonce(); }
  uint32_t applied_setpoint_generation() const { return session_.setpoints().applied(); }
  /// UpdateReboot was acknowledged: the shell resets the board once the Ack is sent.
  bool reboot_requested() const { return reboot_requested_; }
  /// The live configuration's memory, for tests that corrupt it on purpose.
  BoardConfig& live_config_for_test() { return live_; }

 private:
  friend class BoardDispatch;
  friend class BoardReports;

  // Out of line, so instruction counts can bracket a tick (tests/bench/qemu_insn_count.c).
  [[gnu::noinline]] void Tick(uint64_t now_us);
  void ReadInputs(uint64_t now_us, SupervisorInput& in);
  /// The slow monitors' view of the line they visit this tick: where the last tick left it.
  void ObserveSlowSlot();
  /// Fingers in target mode write their lines' setpoints and status bits (nothing while safe).
  /// Out of line, so instruction counts can bracket the finger stage (its steps are inlined).
  [[gnu::noinline]] void ComputeSetpoints(uint64_t now_us);
  /// line_flags_ from the fingers' modes (kRaw on a raw finger's lines; kSaturated cleared).
  void RefreshLineFlags();
  /// Every line one step (or held safe), DAC codes into dac_codes_. Out of line, so instruction
  /// counts can bracket the line stage (its steps are inlined).
  [[gnu::noinline]] void StepLines();
  void WriteOutputs();
  /// Writes their old line's safe code to the channels a configuration dropped that have not
  /// taken it yet; returns the first whose write failed, or kNoLine.
  uint8_t ParkDroppedChannels();
  void CheckConfigIntegrity(uint64_t now_us);
  /// Out of line, so instruction counts can bracket the telemetry stage.
  [[gnu::noinline]] void SampleTelemetry(uint64_t now_us, bool fault_report);
  /// The samples batched so far as one Telemetry frame (none: nothing sent).
  void SendTelemetryBatch(uint16_t decimation, bool fault_report);
  /// Link input and output between ticks. Out of line, so instruction counts can bracket a poll.
  [[gnu::noinline]] void Poll(uint64_t now_us);
  void ApplyLive(uint64_t now_us);
  void Hold();  ///< outputs safe until new setpoints arrive; compensators re-home
  /// Close or host silence: outputs safe from this tick on, no new session state, an update
  /// abandoned (what it wrote stays, so it can be resumed).
  void EndSession();
  /// A fresh frame of the session at `now_us`: the host-silence timer starts again.
  void HeardFromHost(uint64_t now_us);
  /// Every line's DAC resolution and signal range are what the board's DAC reports: a 16-bit
  /// line on a 12-bit DAC, or 4–20 mA on a 0–10 V output, would command the wrong pressure.
  bool DacMatches(const BoardConfig& config, ConfigError* error) const;

  BoardConfig factory_;
  BoardIo io_;
  BoardIdentity identity_;
  BoardConfig live_{};
  BoardConfig candidate_{};  ///< configuration being validated before it replaces live_
  ConfigStore store_;
  bool config_is_default_ = true;
  bool config_saved_ = false;    ///< a saved copy is what the next boot loads
  bool config_unsaved_ = false;  ///< the live configuration differs from what the next boot loads

  protocol::BoardSession session_;
  protocol::OwningFrameDecoder decoder_;
  TxQueue tx_;
  uint64_t last_host_frame_us_ = 0;  ///< the session's last fresh frame

  TickPacer pacer_{kTickUs};
  SupervisorSettings settings_{};
  /// Rewritten for every configured line each tick, so not rebuilt (zeroing it cost ≈ 900
  /// instructions a tick with the C library's byte-wise memset); reset when the configuration
  /// changes, so lines beyond the count stay unconfigured.
  SupervisorInput supervisor_input_{};
  SupervisorState supervisor_{};
  bool released_ =
      false;  ///< new setpoints arrived since Hello, the last shutdown, clear or release
  bool safe_ = true;
  bool estop_requested_ = false;
  bool reboot_requested_ = false;

  std::array<LineParams, protocol::kMaxLines> line_params_{};
  std::array<LineState, protocol::kMaxLines> line_state_{};
  std::array<LineOutput, protocol::kMaxLines> line_out_{};
  /// What the DAC is given each tick, one scan of the configured lines (safe codes until a tick).
  std::array<uint32_t, protocol::kMaxLines> dac_codes_{};
  /// What each line steps towards: the host's raw setpoint, or what its finger in target mode
  /// wrote this tick (the host cannot send raw setpoints for such a line).
  std::array<float, protocol::kMaxLines> setpoint_pa_{};
  /// Status bits a line's finger adds to it: kRaw while the finger is in raw mode, kSaturated
  /// while its compensator is clamped (written by each step; cleared when the board goes safe).
  std::array<uint8_t, protocol::kMaxLines> line_flags_{};
  std::array<FingerParams, protocol::kMaxFingers> finger_params_{};
  std::array<FingerState, protocol::kMaxFingers> finger_state_{};
  std::array<uint8_t, protocol::kMaxLines> line_owner_{};
  uint8_t driven_lines_ = 0;        ///< DAC channels the live configuration's lines write each tick
  uint32_t unparked_channels_ = 0;  ///< dropped channels whose safe code is not written yet

  hal::PulsingEnable supply_pulse_;
  hal::PulsingEnable dump_pulse_;

  /// CRC of the live configuration's wire form (GetConfig reports it), once per configuration:
  /// computing it takes ≈ 15 000 instructions, too many to repeat for every chunk a host reads.
  uint32_t config_crc_ = 0;
  // Integrity of the live configuration: a CRC over its memory, recomputed a slice per tick.
  uint32_t config_memory_crc_ = 0;
  uint32_t check_crc_ = 0;
  uint32_t check_offset_ = 0;
  uint64_t next_check_us_ = 0;
  bool config_intact_ = true;

  // Telemetry batching.
  protocol::Telemetry batch_{};
  uint32_t tick_index_ = 0;

  // Staged configuration upload.
  std::array<uint8_t, protocol::kMaxStagedBytes> staged_{};
  uint16_t staged_expected_ = 0;
  uint16_t staged_received_ = 0;
  uint32_t staged_crc_ = 0;  ///< of the bytes received, part by part: the commit only compares
};

}  // namespace palpa::core
