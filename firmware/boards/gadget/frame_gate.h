// Board output into the USB link as a board's own small transmit buffer takes it: whole frames,
// telemetry dropped and counted when the link is full, everything else (answers, fault reports)
// held until there is room. The bridge reads the simulated board at once instead of pushing back
// on it, so no second of stale telemetry piles up in socket buffers while no host reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "palpa/hal/byte_link.h"
#include "palpa/protocol/framing.h"

namespace palpa::gadget {

class FrameGate {
 public:
  /// Bytes from the board: split into frames at each delimiter, each passed on or dropped.
  void FromBoard(const uint8_t* data, size_t size, hal::ByteLink& link);
  /// Held frames into the link, oldest first, as far as there is room.
  void Flush(hal::ByteLink& link);
  uint64_t telemetry_dropped() const { return telemetry_dropped_; }
  uint64_t other_dropped() const { return other_dropped_; }
  size_t held() const { return held_.size(); }

 private:
  void Frame(bool telemetry, hal::ByteLink& link);

  protocol::OwningFrameDecoder decoder_;
  std::vector<uint8_t> frame_;
  std::deque<std::vector<uint8_t>> held_;
  uint64_t telemetry_dropped_ = 0;
  uint64_t other_dropped_ = 0;
  static constexpr size_t kMaxHeld = 256;
};

}  // namespace palpa::gadget
