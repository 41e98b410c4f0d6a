// Reports the board sends: HelloReply, loop statistics, diagnostics, configuration read-back.
#pragma once

#include <cstdint>

#include "palpa/protocol/messages_admin.h"
#include "palpa/protocol/messages_update.h"
#include "palpa/protocol/status.h"

namespace palpa::core {

class Board;

/// Each queues one answer frame (dropped and counted when the answer queue is full).
class BoardReports {
 public:
  static void HelloReply(Board& board, uint32_t host_nonce, uint8_t seq);
  static void LoopStats(Board& board, uint8_t seq);
  static void Diagnostics(Board& board, uint8_t seq);
  /// kNotFound for a section that does not exist, kOutOfRange for an offset past its end.
  static protocol::Status ConfigReport(Board& board, const protocol::GetConfig& request,
                                       uint8_t seq);
  /// Reports of the update set, stamped with the boot nonce.
  static void UpdateStatus(Board& board, protocol::UpdateStatus report, uint8_t seq);
  static void Slots(Board& board, protocol::SlotsReport report, uint8_t seq);
};

}  // namespace palpa::core
