// Internal to firmware/core: the telemetry batch — line samples gathered tick by tick (decimated)
// and sent as one Telemetry frame when full, or at once, with the fault's own tick, when a fault
// needs reporting.
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/internal/board_lines.h"
#include "palpa/core/supervisor.h"
#include "palpa/core/tx_queue.h"
#include "palpa/protocol/messages_report.h"
#include "palpa/protocol/session.h"

namespace palpa::core {

class TelemetryBatch {
 public:
  /// What the tick knows that the batch reports.
  struct Tick {
    uint64_t now_us = 0;
    bool fault_report = false;  ///< a fault latched this tick: send what there is now
    uint32_t latched_faults = 0;
  };

  /// A new live configuration: its decimation, batch size and line count from now on.
  void Apply(const BoardConfig& live, uint32_t tick_us) {
    decimation_ = live.board.telemetry_decimation;
    batch_ticks_ = live.board.telemetry_batch;
    sample_interval_us_ = tick_us * decimation_;
  }

  /// Samples the lines on every decimation-th tick of an open session, and on the tick a fault
  /// is to be reported; queues the batch when full or at once for the fault. Out of line, so
  /// instruction counts can bracket the telemetry stage.
  [[gnu::noinline]] void Sample(const Tick& tick, const BoardLines& lines,
                                const SupervisorInput& in, const protocol::BoardSession& session,
                                TxQueue& tx);

 private:
  /// The samples batched so far as one Telemetry frame (none: nothing sent).
  void Send(uint32_t latched_faults, bool fault_report, const BoardLines& lines,
            const protocol::BoardSession& session, TxQueue& tx);

  protocol::Telemetry batch_{};
  uint32_t tick_index_ = 0;
  uint16_t decimation_ = 1;
  uint16_t batch_ticks_ = 1;
  uint32_t sample_interval_us_ = 0;
};

}  // namespace palpa::core
