// Frame-at-a-time forwarding with the board's transmit priorities.
#include "frame_gate.h"

#include "palpa/protocol/message_info.h"

namespace palpa::gadget {

void FrameGate::FromBoard(const uint8_t* data, size_t size, hal::ByteLink& link) {
  for (size_t i = 0; i < size; ++i) {
    frame_.push_back(data[i]);
    const auto event = decoder_.Process(data[i]);
    if (data[i] != protocol::kFrameDelimiter) continue;
    Frame(
        event == protocol::FrameDecoder::Event::kFrame &&
            decoder_.frame().header.type == static_cast<uint8_t>(protocol::MessageType::kTelemetry),
        link);
    frame_.clear();
  }
}

void FrameGate::Frame(bool telemetry, hal::ByteLink& link) {
  Flush(link);
  if (held_.empty() && link.WriteSpace() >= frame_.size()) {
    link.Write(frame_.data(), frame_.size());
  } else if (telemetry) {
    ++telemetry_dropped_;  // as the board drops a whole telemetry frame under back-pressure
  } else {
    if (held_.size() >= kMaxHeld) {  // a link that never drains: the oldest answer goes
      held_.pop_front();
      ++other_dropped_;
    }
    held_.push_back(frame_);
  }
}

void FrameGate::Flush(hal::ByteLink& link) {
  while (!held_.empty() && link.WriteSpace() >= held_.front().size()) {
    link.Write(held_.front().data(), held_.front().size());
    held_.pop_front();
  }
}

}  // namespace palpa::gadget
