// Priority transmit queue over a non-blocking link.
#include "palpa/core/tx_queue.h"

namespace palpa::core {

uint8_t* TxQueue::ReserveAnswer() {
  if (answer_count_ == kAnswerSlots) {
    ++answers_dropped_;
    return nullptr;
  }
  return answers_[(answer_head_ + answer_count_) % kAnswerSlots].bytes;
}

void TxQueue::CommitAnswer(size_t size) {
  answers_[(answer_head_ + answer_count_) % kAnswerSlots].size = static_cast<uint16_t>(size);
  ++answer_count_;
}

uint8_t* TxQueue::ReserveTelemetry(bool fault_report) {
  Slot& slot = fault_report ? fault_report_ : telemetry_;
  if (&slot == sending_) {  // still going out: the new frame is the one dropped
    ++telemetry_dropped_;
    return nullptr;
  }
  return slot.bytes;
}

void TxQueue::CommitTelemetry(size_t size, bool fault_report) {
  Slot& slot = fault_report ? fault_report_ : telemetry_;
  if (slot.size != 0) ++telemetry_dropped_;  // the previous frame never left: newest wins
  slot.size = static_cast<uint16_t>(size);
  // Samples go out in the order they were taken: a frame still waiting when a fault report
  // comes holds older ticks, and goes first.
  if (fault_report) telemetry_first_ = telemetry_.size != 0;
}

void TxQueue::Flush(hal::ByteLink& link) {
  for (;;) {
    if (sending_ == nullptr) {
      if (answer_count_ > 0) {
        sending_ = &answers_[answer_head_];
      } else if (fault_report_.size != 0 && !(telemetry_first_ && telemetry_.size != 0)) {
        sending_ = &fault_report_;
      } else if (telemetry_.size != 0) {
        sending_ = &telemetry_;
        telemetry_first_ = false;
      } else {
        return;
      }
      sent_ = 0;
    }
    const size_t written = link.Write(sending_->bytes + sent_, sending_->size - sent_);
    sent_ = static_cast<uint16_t>(sent_ + written);
    if (sent_ < sending_->size) return;  // link full: continue on the next poll
    if (sending_ == &answers_[answer_head_] && answer_count_ > 0) {
      answer_head_ = static_cast<uint8_t>((answer_head_ + 1) % kAnswerSlots);
      --answer_count_;
    }
    sending_->size = 0;
    sending_ = nullptr;
  }
}

}  // namespace palpa::core
