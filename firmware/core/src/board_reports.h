// Private to the core: the reports the board sends — HelloReply, loop statistics, diagnostics,
// configuration read-back and the update set's — from a read-only view of its state.
#pragma once

#include <cstdint>

#include "palpa/core/board.h"
#include "palpa/protocol/messages_admin.h"
#include "palpa/protocol/messages_update.h"
#include "palpa/protocol/status.h"

namespace palpa::core {

class UpdateEngine;

/// What the reports read, and the queue they answer into.
struct ReportContext {
  const BoardIdentity& identity;
  const LiveConfig& config;
  const BoardFingers& fingers;
  const BoardLines& lines;
  const protocol::BoardSession& session;
  const SupervisorState& supervisor;
  const TickPacer& pacer;
  const protocol::FramingCounters& rx;
  hal::Clock& clock;
  UpdateEngine* update;  ///< nullptr: no updates (reading its floor reads flash)
  TxQueue& tx;
};

/// Each queues one answer frame (dropped and counted when the answer queue is full).
namespace reports {

void HelloReply(const ReportContext& board, uint32_t host_nonce, uint8_t seq);
void LoopStats(const ReportContext& board, uint8_t seq);
void Diagnostics(const ReportContext& board, uint8_t seq);
/// kNotFound for a section that does not exist, kOutOfRange for an offset past its end.
protocol::Status ConfigReport(const ReportContext& board, const protocol::GetConfig& request,
                              uint8_t seq);
/// Reports of the update set, stamped with the boot nonce.
void UpdateStatus(const ReportContext& board, protocol::UpdateStatus report, uint8_t seq);
void Slots(const ReportContext& board, protocol::SlotsReport report, uint8_t seq);

}  // namespace reports
}  // namespace palpa::core
