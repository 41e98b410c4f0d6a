// The control tick: sensing → supervisor → fingers → lines → outputs → telemetry, each stage
// through its owner (board_lines_tick.cc, board_fingers_tick.cc, telemetry_batch.cc).
#include "palpa/core/board.h"
#include "palpa/core/update_engine.h"

namespace palpa::core {

void Board::Tick(uint64_t now_us) {
  pacer_.BeginTick(now_us);
  SupervisorInput& in = supervisor_input_;
  in.now_us = now_us;
  in.session_open = session_.open();
  in.last_host_frame_us = session_.last_frame_us();
  in.actuating = released_;
  in.estop_pin = io_.estop != nullptr && io_.estop->Read();
  in.safe = safe_;
  if (io_.adc != nullptr) lines_.Sense(*io_.adc, in);
  in.config_intact = check_.Step(config_.live(), now_us);
  // An EStop latched its fault when it arrived; this tick's telemetry reports it.
  const bool estop_arrived = estop_requested_;
  estop_requested_ = false;
  // The slow monitors' view of the line they visit this tick: where the last tick left it.
  const uint8_t slot = SlowSlot(supervisor_);
  if (slot < lines_.count()) lines_.Observe(slot, in.lines[slot]);
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

  // Fingers in target mode write their lines' setpoints and status bits (nothing while safe:
  // the lines hold their safe values, and the fingers re-home when it ends).
  if (!safe_) {
    fingers_.Step(FingerTick{now_us, fingers_.home_dwell_us(), lines_.setpoints(), lines_.flags()},
                  in.lines.data(), lines_.states());
  }
  lines_.Step(safe_, in);
  WriteOutputs();
  telemetry_.Sample({now_us, newly != 0 || estop_arrived, supervisor_.latched}, lines_, in,
                    session_, tx_);
  if (silent) EndSession();
  pacer_.EndTick(io_.clock.NowMicros());
}

void Board::WriteOutputs() {
  using protocol::OutputKind;
  using protocol::OutputWriteDetail;
  // The supervisor judges a failed write on the next tick: the first output that failed.
  int32_t failed = kNoFailedOutput;
  auto note = [&failed](bool written, int32_t detail) {
    if (!written && failed == kNoFailedOutput) failed = detail;
  };
  const uint8_t dac = lines_.WriteDac(io_.dac);
  note(dac == protocol::kNoLine, OutputWriteDetail(OutputKind::kDac, dac));
  // Critical for safety: valves and pump are held only while the board is not safe (read once:
  // the calls between could change it, for all the compiler knows).
  const bool hold = !safe_;
  note(supply_pulse_.Tick(hold) == Status::kOk, OutputWriteDetail(OutputKind::kSupplyEnable));
  note(dump_pulse_.Tick(hold) == Status::kOk, OutputWriteDetail(OutputKind::kDumpEnable));
  // The lines' own dump valves: open where a line vents toward atmosphere, every one while safe
  // (BoardLines::vents); written when that changes, and again each tick after a failed write.
  const uint32_t vents = lines_.vents();
  if (vents != vents_written_) {
    vents_written_ = vents;
    if (io_.line_vents != nullptr) {
      const uint8_t valve = io_.line_vents->Write(vents);
      if (valve != hal::DigitalPort::kAllWritten) {
        vents_written_ = ~0u;
        note(false, OutputWriteDetail(OutputKind::kLineValve, valve));
      }
    }
  }
  note(io_.pump_enable.Set(hold && supervisor_.pump_on) == Status::kOk,
       OutputWriteDetail(OutputKind::kPumpEnable));
  supervisor_input_.failed_output = failed;
}

}  // namespace palpa::core
