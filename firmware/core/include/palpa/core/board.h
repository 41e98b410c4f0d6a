// The board's brain: configuration, session, supervisor, fingers and lines, run from a loop shell
// that calls Step(). Talks to hardware only through hal interfaces.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/internal/board_fingers.h"
#include "palpa/core/internal/board_lines.h"
#include "palpa/core/internal/config_check.h"
#include "palpa/core/internal/live_config.h"
#include "palpa/core/internal/staged_config.h"
#include "palpa/core/internal/telemetry_batch.h"
#include "palpa/core/supervisor.h"
#include "palpa/core/tick_pacer.h"
#include "palpa/core/tx_queue.h"
#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/flash.h"
#include "palpa/protocol/catalog.h"
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
  /// Bit i opens line i's dump valve while the dump enable holds the others shut (a set bit
  /// releases the valve's driver: open is its unpowered, safe position). nullptr: no per-line
  /// valve drivers, the dump valves move only together.
  hal::DigitalPort* line_vents = nullptr;
  /// The board's own refusal of a line its hardware cannot keep safe, checked with every new
  /// configuration: the reason, or nullptr to accept. nullptr: no check beyond the core's.
  LineCheck line_check = nullptr;
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

struct ReportContext;  // what the board's reports read (src/board_reports.h)

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
  const BoardConfig& config() const { return config_.live(); }
  uint32_t latched_faults() const { return supervisor_.latched; }
  uint32_t active_conditions() const { return supervisor_.active; }
  bool safe() const { return safe_; }
  const LineOutput& line_output(uint8_t line) const { return lines_.output(line); }
  /// The lines whose dump valves are open, one bit each (BoardIo::line_vents).
  uint32_t line_vents() const { return lines_.vents(); }
  uint32_t dac_code(uint8_t line) const { return lines_.dac_code(line); }
  const LineState& line_state(uint8_t line) const { return lines_.state(line); }
  const TickStats& tick_stats() const { return pacer_.stats(); }
  const protocol::FramingCounters& rx_counters() const { return decoder_.counters(); }
  const TxQueue& tx() const { return tx_; }
  bool config_is_default() const { return config_.is_default(); }
  bool config_saved() const { return config_.saved(); }
  bool config_unsaved() const { return config_.unsaved(); }
  /// When the session's host last sent a fresh frame (Hello, a newer heartbeat, an applied
  /// command or stream frame): what the host-silence timer counts from.
  uint64_t last_host_frame_us() const { return session_.last_frame_us(); }
  bool session_open() const { return session_.open(); }
  /// The open session's identity: its Hello's nonce, which its frames carry.
  uint32_t session_nonce() const { return session_.host_nonce(); }
  uint32_t applied_setpoint_generation() const { return session_.setpoints().applied(); }
  uint32_t applied_target_generation() const { return session_.targets().applied(); }
  /// UpdateReboot was acknowledged: the shell resets the board once the Ack is sent.
  bool reboot_requested() const { return reboot_requested_; }
  /// The live configuration's memory, for tests that corrupt it on purpose.
  BoardConfig& live_config_for_test() { return config_.live_for_test(); }

 private:
  /// A handler's answer: a status for Ack/Nack, or a report it has already queued.
  struct HandlerAnswer {
    Status status = Status::kOk;
    uint32_t detail = 0;
    bool replied = false;  ///< a report went out instead of an Ack
  };

  // The tick (board_tick.cc): inputs → supervisor → fingers → lines → outputs → telemetry.
  // Out of line, so instruction counts can bracket a tick (tests/bench/qemu_insn_count.c).
  [[gnu::noinline]] void Tick(uint64_t now_us);
  void WriteOutputs();
  /// A new live configuration reaches every stage; outputs held safe until new setpoints.
  void ApplyLive(uint64_t now_us);
  void Hold();  ///< outputs safe until new setpoints arrive; compensators re-home
  /// Close or host silence: outputs safe from this tick on, no new session state, an update
  /// abandoned (what it wrote stays, so it can be resumed).
  void EndSession();
  /// What the reports read (board_reports.h).
  ReportContext Reports();

  // The link (board_dispatch.cc): frames in, session and reliable-channel rules, one handler per
  // message (board_dispatch.cc, board_config_dispatch.cc, board_update_dispatch.cc).
  /// Link input and output between ticks. Out of line, so instruction counts can bracket a poll.
  [[gnu::noinline]] void Poll(uint64_t now_us);
  void OnFrame(const protocol::Frame& frame, uint64_t now_us);
  HandlerAnswer Handle(const protocol::Frame& frame, uint64_t now_us);
  void Answer(uint8_t type, uint8_t seq, uint8_t answer_flags, Status status, uint32_t detail);
  HandlerAnswer Apply(const protocol::Hello& m, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::EStop&, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::Close& m, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::Release& m, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::Heartbeat& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::SetLineSetpoints& m, const protocol::Header&,
                      uint64_t now_us);
  HandlerAnswer Apply(const protocol::SetFingerTargets& m, const protocol::Header&,
                      uint64_t now_us);
  HandlerAnswer Apply(const protocol::SetFingerMode& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::ConfigureLine& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::ConfigureFinger& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::ConfigureBoard& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::StagedBegin& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::StagedPart& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::StagedCommit& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::GetConfig& m, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::SaveConfig&, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::FactoryReset&, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::ClearFault& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::GetLoopStats&, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::GetDiagnostics&, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateEnter& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateErase& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateWrite& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateQuery& m, const protocol::Header& h, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateActivate& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateReboot&, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::UpdateConfirm& m, const protocol::Header&, uint64_t now_us);
  HandlerAnswer Apply(const protocol::SlotsQuery&, const protocol::Header& h, uint64_t now_us);
  /// Everything else: board-to-host messages.
  template <class M>
  HandlerAnswer Apply(const M&, const protocol::Header&, uint64_t) {
    return {Status::kUnsupported};
  }
  /// The edited candidate made live, or the refusal.
  HandlerAnswer CommitCandidate(uint64_t now_us);

  BoardIo io_;
  BoardIdentity identity_;

  // What each stage owns (internal/): the tick and the handlers reach them only through their
  // interfaces.
  LiveConfig config_;
  StagedConfig staged_;
  ConfigCheck check_;
  BoardLines lines_;
  BoardFingers fingers_;
  TelemetryBatch telemetry_;
  protocol::BoardSession session_;
  protocol::OwningFrameDecoder decoder_;
  TxQueue tx_;
  TickPacer pacer_{kTickUs};

  // The tick's sequence and the board's safety state.
  SupervisorSettings settings_{};
  /// Rewritten for every configured line each tick, so not rebuilt (zeroing it cost ≈ 900
  /// instructions a tick with the C library's byte-wise memset); reset when the configuration
  /// changes, so lines beyond the count stay unconfigured.
  SupervisorInput supervisor_input_{};
  SupervisorState supervisor_{};
  /// New setpoints arrived since Hello, the last shutdown, clear or release.
  bool released_ = false;
  bool safe_ = true;
  bool estop_requested_ = false;
  bool reboot_requested_ = false;
  hal::PulsingEnable supply_pulse_;
  hal::PulsingEnable dump_pulse_;
  /// The line vents last written (none yet, or the write failed: no line mask).
  uint32_t vents_written_ = ~0u;
};

}  // namespace palpa::core
