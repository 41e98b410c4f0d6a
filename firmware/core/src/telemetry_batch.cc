// The telemetry batch: line samples gathered tick by tick, queued as one frame.
#include "palpa/core/internal/telemetry_batch.h"

#include "palpa/protocol/codec.h"

namespace palpa::core {
namespace {

/// Telemetry carries readings within ±200 kPa; a sensor gone wild still fits the field.
int32_t ClampReading(float pa) {
  return pa > 200000.0f ? 200000 : (pa < -200000.0f ? -200000 : static_cast<int32_t>(pa));
}

}  // namespace

void TelemetryBatch::Sample(const Tick& tick, const BoardLines& lines, const SupervisorInput& in,
                            const protocol::BoardSession& session, TxQueue& tx) {
  if (!session.open()) return;
  const uint32_t phase = tick_index_++ % decimation_;
  // A fault is reported with the tick it latched in (its outputs already safe), even between two
  // decimated samples, as a session that falls silent sends nothing after it: the samples so far
  // go first with their own timing, and the schedule starts again at this tick.
  if (tick.fault_report && phase != 0) {
    Send(tick.latched_faults, false, lines, session, tx);
    tick_index_ -= phase;
  }
  if (phase == 0 || tick.fault_report) {
    if (batch_.tick_count == 0) batch_.first_sample_us = tick.now_us;
    for (uint8_t i = 0; i < lines.count(); ++i) {
      const LineOutput& o = lines.output(i);
      const LineObservation& seen = in.lines[i];
      batch_.samples[batch_.sample_count++] =
          protocol::LineSample{static_cast<int32_t>(lines.state(i).slewed_pa),
                               seen.reading.valid ? ClampReading(seen.reading.pa) : 0,
                               static_cast<uint16_t>(lines.dac_code(i)), o.status};
    }
    ++batch_.tick_count;
  }
  if (batch_.tick_count >= batch_ticks_ || tick.fault_report)
    Send(tick.latched_faults, tick.fault_report, lines, session, tx);
}

void TelemetryBatch::Send(uint32_t latched_faults, bool fault_report, const BoardLines& lines,
                          const protocol::BoardSession& session, TxQueue& tx) {
  if (batch_.tick_count == 0) return;
  batch_.boot_nonce = session.boot_nonce();
  batch_.sample_interval_us = sample_interval_us_;
  batch_.line_count = lines.count();
  batch_.setpoint_generation = session.setpoints().applied();
  batch_.target_generation = session.targets().applied();
  batch_.fault_bitmap = latched_faults;
  batch_.dropped_frames = tx.telemetry_dropped();
  uint8_t* slot = tx.ReserveTelemetry(fault_report);
  if (slot != nullptr) {
    const uint8_t flags = static_cast<uint8_t>(
        protocol::flags::kFromBoard | (latched_faults != 0 ? protocol::flags::kFaulted : 0));
    const auto n = protocol::EncodeMessageFrame(batch_, static_cast<uint8_t>(tick_index_), flags,
                                                slot, protocol::kMaxFrameSize);
    if (n.ok()) tx.CommitTelemetry(n.value, fault_report);
  }
  batch_.tick_count = 0;
  batch_.sample_count = 0;
}

}  // namespace palpa::core
