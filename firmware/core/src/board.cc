// The board: start-up, the main loop pass, and a configuration reaching every stage.
#include "palpa/core/board.h"

#include "board_reports.h"
#include "palpa/core/update_engine.h"

namespace palpa::core {

using protocol::Fault;

Board::Board(const BoardConfig& factory, BoardIo io, BoardIdentity identity)
    : io_(io),
      identity_(identity),
      config_(factory, io.flash, io.flash_config_base, io.dac, io.line_check),
      session_(identity.boot_nonce),
      supply_pulse_(io.supply_enable),
      dump_pulse_(io.dump_enable) {}

void Board::Start() {
  // Critical for safety: every output to its safe code before anything else happens.
  const uint64_t now = io_.clock.NowMicros();
  config_.Load();
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
  const BoardConfig& live = config_.live();
  settings_ = MakeSupervisorSettings(live.board);
  supervisor_input_ = SupervisorInput{};
  lines_.Apply(live, kTickUs, io_.adc != nullptr, supervisor_input_, io_.dac);
  fingers_.Apply(live);
  telemetry_.Apply(live, kTickUs);
  check_.Restart(live, now_us);
  Hold();
}

void Board::Hold() {
  released_ = false;
  fingers_.Hold();
  fingers_.MarkRawLines(lines_.flags());
}

void Board::EndSession() {
  Hold();
  safe_ = true;  // Critical for safety: as for EStop, the next tick's outputs are safe codes
  session_.End();
  if (io_.update != nullptr) io_.update->LeaveUpdateMode();
}

ReportContext Board::Reports() {
  return ReportContext{identity_, config_,     fingers_, lines_,
                       session_,  supervisor_, pacer_,   decoder_.counters(),
                       io_.clock, io_.update,  tx_};
}

}  // namespace palpa::core
