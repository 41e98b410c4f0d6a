// Frame decoder: CRC and COBS around a packet, with resynchronisation on 0x00.
#include "palpa/protocol/framing.h"

#include "palpa/protocol/crc32.h"

namespace palpa::protocol {

FrameDecoder::Event FrameDecoder::Process(uint8_t byte) {
  if (byte == kFrameDelimiter) return Finish();
  ++raw_bytes_;
  if (overflowed_) return Event::kNone;  // discard until the next delimiter
  uint8_t decoded[2];
  const size_t n = cobs_.Feed(byte, decoded);
  if (length_ + n > capacity_) {
    overflowed_ = true;
    return Event::kNone;
  }
  for (size_t i = 0; i < n; ++i) buffer_[length_++] = decoded[i];
  return Event::kNone;
}

FrameDecoder::Event FrameDecoder::Finish() {
  const size_t length = length_;
  const bool overflowed = overflowed_;
  const bool complete = cobs_.Complete();
  const size_t raw = raw_bytes_;
  length_ = 0;
  raw_bytes_ = 0;
  overflowed_ = false;
  cobs_.Reset();

  if (raw == 0) {
    ++counters_.empty;
    return Event::kNone;
  }
  Status error = Status::kOk;
  if (overflowed) {
    ++counters_.oversize;
    error = Status::kOverflow;
  } else if (!complete || length < kHeaderSize + kCrcSize) {
    ++counters_.garbage;
    error = Status::kBadLength;
  } else {
    const size_t packet_size = length - kCrcSize;
    const uint8_t* crc_bytes = buffer_ + packet_size;
    const uint32_t received =
        static_cast<uint32_t>(crc_bytes[0]) | (static_cast<uint32_t>(crc_bytes[1]) << 8) |
        (static_cast<uint32_t>(crc_bytes[2]) << 16) | (static_cast<uint32_t>(crc_bytes[3]) << 24);
    if (packet_size > kMaxPacketSize) {
      ++counters_.oversize;
      error = Status::kOverflow;
    } else if (Crc32(buffer_, packet_size) != received) {
      ++counters_.crc_errors;
      error = Status::kCrcError;
    } else {
      error = ReadHeader(buffer_, packet_size, frame_.header);
      if (error == Status::kVersionError) ++counters_.version_errors;
      if (error == Status::kReservedFlags) ++counters_.flag_errors;
      if (error == Status::kOk) {
        frame_.body = buffer_ + kHeaderSize;
        frame_.body_size = packet_size - kHeaderSize;
        ++counters_.frames;
        return Event::kFrame;
      }
    }
  }
  last_error_ = error;
  return Event::kError;
}

}  // namespace palpa::protocol
