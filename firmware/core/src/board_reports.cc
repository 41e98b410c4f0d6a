// Reports: HelloReply, loop statistics, diagnostics, configuration read-back, update set.
#include "board_reports.h"

#include <cstring>

#include "palpa/core/update_engine.h"
#include "palpa/protocol/codec.h"

namespace palpa::core {
namespace {

namespace flags = protocol::flags;

uint8_t BoardFlags(const ReportContext& b, uint8_t extra) {
  return static_cast<uint8_t>(flags::kFromBoard | extra |
                              (b.supervisor.latched ? flags::kFaulted : 0));
}

template <class M>
void QueueAnswer(TxQueue& tx, const M& m, uint8_t seq, uint8_t header_flags) {
  uint8_t* slot = tx.ReserveAnswer();
  if (slot == nullptr) return;
  const auto n = protocol::EncodeMessageFrame(m, seq, header_flags, slot, protocol::kMaxFrameSize);
  if (n.ok()) tx.CommitAnswer(n.value);
}

}  // namespace

namespace reports {

void HelloReply(const ReportContext& b, uint32_t host_nonce, uint8_t seq) {
  protocol::HelloReply r{};
  const BoardIdentity& id = b.identity;
  r.host_nonce = host_nonce;
  r.boot_nonce = b.session.boot_nonce();
  r.board_kind = id.kind;
  r.board_id = id.board_id;
  r.protocol_version = protocol::kProtocolVersion;
  r.firmware_major = id.firmware_major;
  r.firmware_minor = id.firmware_minor;
  r.firmware_patch = id.firmware_patch;
  r.catalog_hash = protocol::kCatalogHash;
  r.reset_cause = id.reset_cause;
  r.config_is_default = b.config.is_default();
  r.plant_simulated = id.plant_simulated;
  r.time_scale = id.time_scale;
  r.rx_buffer_bytes = id.rx_buffer_bytes;
  r.active_slot = id.active_slot;
  r.rollback_counter = b.update != nullptr ? b.update->rollback_floor() : id.rollback_counter;
  r.host_timeout_us = b.config.live().board.host_timeout_us;
  r.fault_bitmap = b.supervisor.latched;
  r.config_name = b.config.live().board.config_name;
  r.line_count = b.config.live().line_count;
  for (uint8_t i = 0; i < b.config.live().line_count; ++i) {
    const protocol::ConfigureLine& c = b.config.live().lines[i];
    r.lines[i] = protocol::LineSummary{c.kind, c.sensor != protocol::SensorKind::kNone,
                                       c.limit_min_pa, c.limit_max_pa};
  }
  r.finger_count = b.config.live().finger_count;
  for (uint8_t f = 0; f < b.config.live().finger_count; ++f) {
    const protocol::ConfigureFinger& c = b.config.live().fingers[f];
    r.fingers[f] = protocol::FingerSummary{c.kind, b.fingers.mode(f), c.line_a, c.line_b};
  }
  QueueAnswer(b.tx, r, seq, BoardFlags(b, 0));
}

void LoopStats(const ReportContext& b, uint8_t seq) {
  const TickStats& t = b.pacer.stats();
  protocol::LoopStats s{};
  s.boot_nonce = b.session.boot_nonce();
  s.ticks = t.ticks;
  s.period_us = b.pacer.period_us();
  s.jitter_max_us = t.jitter_max_us;
  s.worst_tick_us = t.worst_tick_us;
  s.mean_tick_us = t.ticks ? static_cast<uint32_t>(t.busy_us / t.ticks) : 0;
  s.overruns = t.overruns;
  s.telemetry_dropped = b.tx.telemetry_dropped();
  const protocol::FramingCounters& rx = b.rx;
  s.rx_frames = rx.frames;
  s.rx_errors = rx.garbage + rx.oversize + rx.crc_errors + rx.version_errors + rx.flag_errors;
  QueueAnswer(b.tx, s, seq, BoardFlags(b, flags::kReliable));
}

void Diagnostics(const ReportContext& b, uint8_t seq) {
  protocol::Diagnostics d{};
  d.boot_nonce = b.session.boot_nonce();
  d.reset_cause = b.identity.reset_cause;
  d.boot_count = b.identity.boot_count;
  d.fault_bitmap = b.supervisor.latched;
  d.active_conditions = b.supervisor.active;
  d.uptime_us = b.clock.NowMicros();
  d.config_saved = b.config.saved();
  d.config_unsaved = b.config.unsaved();
  for (uint8_t i = 0; i < b.lines.count(); ++i)
    if (b.lines.state(i).shaping_fell_back)
      d.shaping_fallback_lines = static_cast<uint8_t>(d.shaping_fallback_lines | 1u << i);
  d.history_count = FaultHistory(b.supervisor, d.history.data());
  QueueAnswer(b.tx, d, seq, BoardFlags(b, flags::kReliable));
}

void UpdateStatus(const ReportContext& b, protocol::UpdateStatus r, uint8_t seq) {
  r.boot_nonce = b.session.boot_nonce();
  QueueAnswer(b.tx, r, seq, BoardFlags(b, flags::kReliable));
}

void Slots(const ReportContext& b, protocol::SlotsReport r, uint8_t seq) {
  r.boot_nonce = b.session.boot_nonce();
  QueueAnswer(b.tx, r, seq, BoardFlags(b, flags::kReliable));
}

protocol::Status ConfigReport(const ReportContext& b, const protocol::GetConfig& request,
                              uint8_t seq) {
  uint8_t body[480];
  protocol::Result<size_t> size = protocol::Status::kNotFound;
  switch (request.section) {
    case protocol::ConfigSection::kBoard:
      size = protocol::EncodeBody(b.config.live().board, body, sizeof(body));
      break;
    case protocol::ConfigSection::kLine:
      if (request.index < b.config.live().line_count)
        size = protocol::EncodeBody(b.config.live().lines[request.index], body, sizeof(body));
      break;
    case protocol::ConfigSection::kFinger:
      if (request.index < b.config.live().finger_count)
        size = protocol::EncodeBody(b.config.live().fingers[request.index], body, sizeof(body));
      break;
    default:
      break;
  }
  if (!size.ok()) return size.status;
  if (request.offset > size.value) return protocol::Status::kOutOfRange;
  protocol::ConfigReport r{};
  r.boot_nonce = b.session.boot_nonce();
  r.section = request.section;
  r.index = request.index;
  r.config_crc = b.config.crc();
  r.total_bytes = static_cast<uint16_t>(size.value);
  r.offset = request.offset;
  const size_t left = size.value - request.offset;
  r.data_size =
      static_cast<uint8_t>(left < protocol::kMaxConfigChunk ? left : protocol::kMaxConfigChunk);
  std::memcpy(r.data.data(), body + request.offset, r.data_size);
  QueueAnswer(b.tx, r, seq, BoardFlags(b, flags::kReliable));
  return protocol::Status::kOk;
}

}  // namespace reports
}  // namespace palpa::core
