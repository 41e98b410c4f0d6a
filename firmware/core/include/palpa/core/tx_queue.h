// Outgoing frames by priority — answers, then fault reports, then telemetry, though never a newer
// tick before an older one — written to a non-blocking link without ever waiting: under
// back-pressure whole telemetry frames are dropped.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "palpa/hal/byte_link.h"
#include "palpa/protocol/wire.h"

namespace palpa::core {

class TxQueue {
 public:
  static constexpr uint8_t kAnswerSlots = 8;

  /// A buffer for the next answer frame, or nullptr when all slots are taken (then the answer
  /// is dropped and counted; the host's retransmission will ask again).
  uint8_t* ReserveAnswer();
  void CommitAnswer(size_t size);

  /// Buffer for the next telemetry frame; `fault_report` frames go before ordinary telemetry.
  uint8_t* ReserveTelemetry(bool fault_report);
  void CommitTelemetry(size_t size, bool fault_report);

  /// Writes as much as the link accepts now, whole frames in priority order.
  void Flush(hal::ByteLink& link);

  uint32_t telemetry_dropped() const { return telemetry_dropped_; }
  uint32_t answers_dropped() const { return answers_dropped_; }

 private:
  struct Slot {
    uint8_t bytes[protocol::kMaxFrameSize];
    uint16_t size = 0;
  };
  std::array<Slot, kAnswerSlots> answers_{};
  uint8_t answer_head_ = 0;
  uint8_t answer_count_ = 0;
  Slot fault_report_{};
  Slot telemetry_{};
  bool telemetry_first_ = false;  ///< telemetry_ holds ticks older than fault_report_
  Slot* sending_ = nullptr;       ///< frame partly written: finish it before anything else
  uint16_t sent_ = 0;
  uint32_t telemetry_dropped_ = 0;
  uint32_t answers_dropped_ = 0;
};

}  // namespace palpa::core
