// Reports: HelloReply, telemetry batches, loop statistics, diagnostics, configuration read-back.
#include "palpa/core/board_reports.h"

#include <cstring>

#include "palpa/core/board.h"
#include "palpa/core/update_engine.h"
#include "palpa/protocol/codec.h"

namespace palpa::core {
namespace {

namespace flags = protocol::flags;

uint8_t BoardFlags(const Board& b, uint8_t extra) {
  return static_cast<uint8_t>(flags::kFromBoard | extra |
                              (b.latched_faults() ? flags::kFaulted : 0));
}

/// Telemetry carries readings within ±200 kPa; a sensor gone wild still fits the field.
int32_t ClampReading(float pa) {
  return pa > 200000.0f ? 200000 : (pa < -200000.0f ? -200000 : static_cast<int32_t>(pa));
}

template <class M>
void QueueAnswer(TxQueue& tx, const M& m, uint8_t seq, uint8_t header_flags) {
  uint8_t* slot = tx.ReserveAnswer();
  if (slot == nullptr) return;
  const auto n = protocol::EncodeMessageFrame(m, seq, header_flags, slot, protocol::kMaxFrameSize);
  if (n.ok()) tx.CommitAnswer(n.value);
}

}  // namespace

void BoardReports::HelloReply(Board& b, uint32_t host_nonce, uint8_t seq) {
  protocol::HelloReply r{};
  const BoardIdentity& id = b.identity_;
  r.host_nonce = host_nonce;
  r.boot_nonce = b.session_.boot_nonce();
  r.board_kind = id.kind;
  r.board_id = id.board_id;
  r.protocol_version = protocol::kProtocolVersion;
  r.firmware_major = id.firmware_major;
  r.firmware_minor = id.firmware_minor;
  r.firmware_patch = id.firmware_patch;
  r.catalog_hash = protocol::kCatalogHash;
  r.reset_cause = id.reset_cause;
  r.config_is_default = b.config_is_default_;
  r.plant_simulated = id.plant_simulated;
  r.time_scale = id.time_scale;
  r.rx_buffer_bytes = id.rx_buffer_bytes;
  r.active_slot = id.active_slot;
  r.rollback_counter =
      b.io_.update != nullptr ? b.io_.update->rollback_floor() : id.rollback_counter;
  r.host_timeout_us = b.live_.board.host_timeout_us;
  r.fault_bitmap = b.supervisor_.latched;
  r.config_name = b.live_.board.config_name;
  r.line_count = b.live_.line_count;
  for (uint8_t i = 0; i < b.live_.line_count; ++i) {
    const protocol::ConfigureLine& c = b.live_.lines[i];
    r.lines[i] = protocol::LineSummary{c.kind, c.sensor != protocol::SensorKind::kNone,
                                       c.limit_min_pa, c.limit_max_pa};
  }
  r.finger_count = b.live_.finger_count;
  for (uint8_t f = 0; f < b.live_.finger_count; ++f) {
    const protocol::ConfigureFinger& c = b.live_.fingers[f];
    r.fingers[f] = protocol::FingerSummary{c.kind, b.finger_state_[f].mode, c.line_a, c.line_b};
  }
  QueueAnswer(b.tx_, r, seq, BoardFlags(b, 0));
}

void BoardReports::LoopStats(Board& b, uint8_t seq) {
  const TickStats& t = b.pacer_.stats();
  protocol::LoopStats s{};
  s.boot_nonce = b.session_.boot_nonce();
  s.ticks = t.ticks;
  s.period_us = b.pacer_.period_us();
  s.jitter_max_us = t.jitter_max_us;
  s.worst_tick_us = t.worst_tick_us;
  s.mean_tick_us = t.ticks ? static_cast<uint32_t>(t.busy_us / t.ticks) : 0;
  s.overruns = t.overruns;
  s.telemetry_dropped = b.tx_.telemetry_dropped();
  const protocol::FramingCounters& rx = b.decoder_.counters();
  s.rx_frames = rx.frames;
  s.rx_errors = rx.garbage + rx.oversize + rx.crc_errors + rx.version_errors + rx.flag_errors;
  QueueAnswer(b.tx_, s, seq, BoardFlags(b, flags::kReliable));
}

void BoardReports::Diagnostics(Board& b, uint8_t seq) {
  protocol::Diagnostics d{};
  d.boot_nonce = b.session_.boot_nonce();
  d.reset_cause = b.identity_.reset_cause;
  d.boot_count = b.identity_.boot_count;
  d.fault_bitmap = b.supervisor_.latched;
  d.active_conditions = b.supervisor_.active;
  d.uptime_us = b.io_.clock.NowMicros();
  d.config_saved = b.config_saved_;
  d.config_unsaved = b.config_unsaved_;
  d.history_count = FaultHistory(b.supervisor_, d.history.data());
  QueueAnswer(b.tx_, d, seq, BoardFlags(b, flags::kReliable));
}

void BoardReports::UpdateStatus(Board& b, protocol::UpdateStatus r, uint8_t seq) {
  r.boot_nonce = b.session_.boot_nonce();
  QueueAnswer(b.tx_, r, seq, BoardFlags(b, flags::kReliable));
}

void BoardReports::Slots(Board& b, protocol::SlotsReport r, uint8_t seq) {
  r.boot_nonce = b.session_.boot_nonce();
  QueueAnswer(b.tx_, r, seq, BoardFlags(b, flags::kReliable));
}

protocol::Status BoardReports::ConfigReport(Board& b, const protocol::GetConfig& request,
                                            uint8_t seq) {
  uint8_t body[480];
  protocol::Result<size_t> size = protocol::Status::kNotFound;
  switch (request.section) {
    case protocol::ConfigSection::kBoard:
      size = protocol::EncodeBody(b.live_.board, body, sizeof(body));
      break;
    case protocol::ConfigSection::kLine:
      if (request.index < b.live_.line_count)
        size = protocol::EncodeBody(b.live_.lines[request.index], body, sizeof(body));
      break;
    case protocol::ConfigSection::kFinger:
      if (request.index < b.live_.finger_count)
        size = protocol::EncodeBody(b.live_.fingers[request.index], body, sizeof(body));
      break;
    default:
      break;
  }
  if (!size.ok()) return size.status;
  if (request.offset > size.value) return protocol::Status::kOutOfRange;
  protocol::ConfigReport r{};
  r.boot_nonce = b.session_.boot_nonce();
  r.section = request.section;
  r.index = request.index;
  r.config_crc = b.config_crc_;
  r.total_bytes = static_cast<uint16_t>(size.value);
  r.offset = request.offset;
  const size_t left = size.value - request.offset;
  r.data_size =
      static_cast<uint8_t>(left < protocol::kMaxConfigChunk ? left : protocol::kMaxConfigChunk);
  std::memcpy(r.data.data(), body + request.offset, r.data_size);
  QueueAnswer(b.tx_, r, seq, BoardFlags(b, flags::kReliable));
  return protocol::Status::kOk;
}

void Board::SampleTelemetry(uint64_t now_us, bool fault_report) {
  if (!session_.open()) return;
  const uint16_t decimation = live_.board.telemetry_decimation;
  const uint32_t phase = tick_index_++ % decimation;
  // A fault is reported with the tick it latched in (its outputs already safe), even between two
  // decimated samples, as a session that falls silent sends nothing after it: the samples so far
  // go first with their own timing, and the schedule starts again at this tick.
  if (fault_report && phase != 0) {
    SendTelemetryBatch(decimation, false);
    tick_index_ -= phase;
  }
  if (phase == 0 || fault_report) {
    if (batch_.tick_count == 0) batch_.first_sample_us = now_us;
    for (uint8_t i = 0; i < live_.line_count; ++i) {
      const LineOutput& o = line_out_[i];
      const LineObservation& seen = supervisor_input_.lines[i];
      batch_.samples[batch_.sample_count++] =
          protocol::LineSample{static_cast<int32_t>(line_state_[i].slewed_pa),
                               seen.reading.valid ? ClampReading(seen.reading.pa) : 0,
                               static_cast<uint16_t>(dac_codes_[i]), o.status};
    }
    ++batch_.tick_count;
  }
  if (batch_.tick_count >= live_.board.telemetry_batch || fault_report)
    SendTelemetryBatch(decimation, fault_report);
}

void Board::SendTelemetryBatch(uint16_t decimation, bool fault_report) {
  if (batch_.tick_count == 0) return;
  batch_.boot_nonce = session_.boot_nonce();
  batch_.sample_interval_us = kTickUs * decimation;
  batch_.line_count = live_.line_count;
  batch_.setpoint_generation = session_.setpoints().applied();
  batch_.target_generation = session_.targets().applied();
  batch_.fault_bitmap = supervisor_.latched;
  batch_.dropped_frames = tx_.telemetry_dropped();
  uint8_t* slot = tx_.ReserveTelemetry(fault_report);
  if (slot != nullptr) {
    const auto n =
        protocol::EncodeMessageFrame(batch_, static_cast<uint8_t>(tick_index_),
                                     BoardFlags(*this, 0), slot, protocol::kMaxFrameSize);
    if (n.ok()) tx_.CommitTelemetry(n.value, fault_report);
  }
  batch_.tick_count = 0;
  batch_.sample_count = 0;
}

}  // namespace palpa::core
