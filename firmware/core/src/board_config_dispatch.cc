// Dispatch of configuration, staged uploads, persistence, fault clearing and queries.
#include <cstring>

#include "board_dispatch.h"
#include "palpa/core/board_reports.h"
#include "palpa/protocol/crc32.h"

namespace palpa::core {

Outcome BoardDispatch::Commit() {
  ConfigError error;
  const Status status = ValidateConfig(b_.candidate_, &error);
  if (status != Status::kOk) return {status, error.detail()};
  if (!b_.DacMatches(b_.candidate_, &error)) return {Status::kBadValue, error.detail()};
  // Between two ticks (dispatch never runs inside one): the whole configuration changes at once.
  std::memcpy(&b_.live_, &b_.candidate_, sizeof(b_.live_));
  b_.config_is_default_ = false;
  b_.config_unsaved_ = true;
  b_.ApplyLive(now_us_);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::ConfigureLine& m, const protocol::Header&) {
  if (m.line > b_.live_.line_count) return {Status::kOutOfRange, m.line};
  std::memcpy(&b_.candidate_, &b_.live_, sizeof(b_.candidate_));
  b_.candidate_.lines[m.line] = m;
  if (m.line == b_.candidate_.line_count) ++b_.candidate_.line_count;
  return Commit();
}

Outcome BoardDispatch::Apply(const protocol::ConfigureFinger& m, const protocol::Header&) {
  if (m.finger > b_.live_.finger_count) return {Status::kOutOfRange, m.finger};
  std::memcpy(&b_.candidate_, &b_.live_, sizeof(b_.candidate_));
  b_.candidate_.fingers[m.finger] = m;
  if (m.finger == b_.candidate_.finger_count) ++b_.candidate_.finger_count;
  return Commit();
}

Outcome BoardDispatch::Apply(const protocol::ConfigureBoard& m, const protocol::Header&) {
  std::memcpy(&b_.candidate_, &b_.live_, sizeof(b_.candidate_));
  b_.candidate_.board = m;
  return Commit();
}

Outcome BoardDispatch::Apply(const protocol::StagedBegin& m, const protocol::Header&) {
  b_.staged_expected_ = m.total_bytes;
  b_.staged_received_ = 0;
  b_.staged_crc_ = 0;
  return {};
}

Outcome BoardDispatch::Apply(const protocol::StagedPart& m, const protocol::Header&) {
  if (b_.staged_expected_ == 0) return {Status::kUnavailable, 0};
  // Parts arrive in order on the reliable channel; anything else is a host bug.
  if (m.offset != b_.staged_received_) return {Status::kOutOfRange, b_.staged_received_};
  if (m.data_size > b_.staged_expected_ - b_.staged_received_)
    return {Status::kOutOfRange, b_.staged_received_};
  std::memcpy(b_.staged_.data() + m.offset, m.data.data(), m.data_size);
  b_.staged_crc_ = protocol::Crc32Update(b_.staged_crc_, m.data.data(), m.data_size);
  b_.staged_received_ = static_cast<uint16_t>(b_.staged_received_ + m.data_size);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::StagedCommit& m, const protocol::Header&) {
  const uint16_t received = b_.staged_received_;
  const bool complete =
      b_.staged_expected_ != 0 && received == b_.staged_expected_ && m.total_bytes == received;
  b_.staged_expected_ = b_.staged_received_ = 0;  // one commit per begin, whatever happens
  if (!complete) return {Status::kStagedIncomplete, received};
  if (b_.staged_crc_ != m.crc32) return {Status::kCrcError, 0};
  std::memcpy(&b_.candidate_, &b_.live_, sizeof(b_.candidate_));
  ConfigError error;
  const Status status = ApplyConfigBlob(b_.staged_.data(), received, b_.candidate_, &error);
  if (status != Status::kOk) return {status, error.detail()};
  return Commit();
}

Outcome BoardDispatch::Apply(const protocol::GetConfig& m, const protocol::Header& h) {
  const Status status = BoardReports::ConfigReport(b_, m, h.seq);
  if (status != Status::kOk) return {status, m.index};
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::SaveConfig&, const protocol::Header&) {
  const Status saved = b_.store_.Save(b_.live_);
  if (saved == Status::kOk) {
    b_.config_saved_ = true;
    b_.config_unsaved_ = false;
  }
  return {saved};
}

Outcome BoardDispatch::Apply(const protocol::FactoryReset&, const protocol::Header&) {
  const Status erased = b_.store_.Erase();
  if (erased != Status::kOk && erased != Status::kUnavailable) return {erased};
  std::memcpy(&b_.live_, &b_.factory_, sizeof(b_.live_));
  b_.config_is_default_ = true;
  b_.config_saved_ = false;  // erased, or nothing persists on this board
  b_.config_unsaved_ = false;
  b_.ApplyLive(now_us_);
  return {};
}

Outcome BoardDispatch::Apply(const protocol::ClearFault& m, const protocol::Header&) {
  // This very frame proves the host is back: host silence no longer persists.
  b_.supervisor_.active &= ~protocol::FaultBit(protocol::Fault::kHostSilence);
  const Status status = ClearFaults(b_.supervisor_, m.mask);
  if (status != Status::kOk)
    return {status, b_.supervisor_.latched & b_.supervisor_.active & m.mask};
  b_.Hold();  // outputs stay safe until new setpoints arrive; compensators re-home
  return {};
}

Outcome BoardDispatch::Apply(const protocol::GetLoopStats&, const protocol::Header& h) {
  BoardReports::LoopStats(b_, h.seq);
  return {Status::kOk, 0, true};
}

Outcome BoardDispatch::Apply(const protocol::GetDiagnostics&, const protocol::Header& h) {
  BoardReports::Diagnostics(b_, h.seq);
  return {Status::kOk, 0, true};
}

}  // namespace palpa::core
