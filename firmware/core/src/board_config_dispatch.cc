// Dispatch of configuration, staged uploads, persistence, fault clearing and queries.
#include "board_reports.h"
#include "palpa/core/board.h"

namespace palpa::core {

Board::HandlerAnswer Board::CommitCandidate(uint64_t now_us) {
  uint32_t detail = 0;
  const Status status = config_.CommitCandidate(detail);
  if (status != Status::kOk) return {status, detail};
  ApplyLive(now_us);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::ConfigureLine& m, const protocol::Header&,
                                  uint64_t now_us) {
  if (m.line > config_.live().line_count) return {Status::kOutOfRange, m.line};
  BoardConfig& candidate = config_.StartCandidate();
  candidate.lines[m.line] = m;
  if (m.line == candidate.line_count) ++candidate.line_count;
  return CommitCandidate(now_us);
}

Board::HandlerAnswer Board::Apply(const protocol::ConfigureFinger& m, const protocol::Header&,
                                  uint64_t now_us) {
  if (m.finger > config_.live().finger_count) return {Status::kOutOfRange, m.finger};
  BoardConfig& candidate = config_.StartCandidate();
  candidate.fingers[m.finger] = m;
  if (m.finger == candidate.finger_count) ++candidate.finger_count;
  return CommitCandidate(now_us);
}

Board::HandlerAnswer Board::Apply(const protocol::ConfigureBoard& m, const protocol::Header&,
                                  uint64_t now_us) {
  config_.StartCandidate().board = m;
  return CommitCandidate(now_us);
}

Board::HandlerAnswer Board::Apply(const protocol::StagedBegin& m, const protocol::Header&,
                                  uint64_t) {
  staged_.Begin(m);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::StagedPart& m, const protocol::Header&,
                                  uint64_t) {
  uint32_t detail = 0;
  const Status status = staged_.Part(m, detail);
  return {status, detail};
}

Board::HandlerAnswer Board::Apply(const protocol::StagedCommit& m, const protocol::Header&,
                                  uint64_t now_us) {
  uint32_t detail = 0;
  Status status = staged_.Commit(m, detail);
  if (status != Status::kOk) return {status, detail};
  status = staged_.ApplyTo(config_.StartCandidate(), detail);
  if (status != Status::kOk) return {status, detail};
  return CommitCandidate(now_us);
}

Board::HandlerAnswer Board::Apply(const protocol::GetConfig& m, const protocol::Header& h,
                                  uint64_t) {
  const Status status = reports::ConfigReport(Reports(), m, h.seq);
  if (status != Status::kOk) return {status, m.index};
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::SaveConfig&, const protocol::Header&, uint64_t) {
  return {config_.Save()};
}

Board::HandlerAnswer Board::Apply(const protocol::FactoryReset&, const protocol::Header&,
                                  uint64_t now_us) {
  const Status status = config_.FactoryReset();
  if (status != Status::kOk) return {status};
  ApplyLive(now_us);
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::ClearFault& m, const protocol::Header&,
                                  uint64_t) {
  // This very frame proves the host is back: host silence no longer persists.
  supervisor_.active &= ~protocol::FaultBit(protocol::Fault::kHostSilence);
  const Status status = ClearFaults(supervisor_, m.mask);
  if (status != Status::kOk) return {status, supervisor_.latched & supervisor_.active & m.mask};
  Hold();  // outputs stay safe until new setpoints arrive; compensators re-home
  return {};
}

Board::HandlerAnswer Board::Apply(const protocol::GetLoopStats&, const protocol::Header& h,
                                  uint64_t) {
  reports::LoopStats(Reports(), h.seq);
  return {Status::kOk, 0, true};
}

Board::HandlerAnswer Board::Apply(const protocol::GetDiagnostics&, const protocol::Header& h,
                                  uint64_t) {
  reports::Diagnostics(Reports(), h.seq);
  return {Status::kOk, 0, true};
}

}  // namespace palpa::core
