// Frame layer: COBS(packet ‖ crc32_le(packet)) ‖ 0x00, decoded a byte at a time.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/cobs.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {

/// Error counters of one decoder; they only grow (wrap at 2^32).
struct FramingCounters {
  uint32_t frames = 0;          ///< good frames delivered
  uint32_t empty = 0;           ///< delimiters with nothing before them (HID padding, resync)
  uint32_t garbage = 0;         ///< malformed COBS or too short for header + CRC
  uint32_t oversize = 0;        ///< longer than kMaxPacketSize + CRC
  uint32_t crc_errors = 0;      ///< CRC mismatch
  uint32_t version_errors = 0;  ///< header version is not kProtocolVersion
  uint32_t flag_errors = 0;     ///< a reserved header flag set
};

/// A decoded frame: valid until the next call to FrameDecoder::Process.
struct Frame {
  Header header;
  const uint8_t* body = nullptr;
  size_t body_size = 0;
};

/// Byte-at-a-time decoder writing into a caller-owned buffer of at least
/// kMaxPacketSize + kCrcSize bytes. Resynchronises on every 0x00.
class FrameDecoder {
 public:
  enum class Event : uint8_t { kNone, kFrame, kError };

  FrameDecoder(uint8_t* buffer, size_t capacity) : buffer_(buffer), capacity_(capacity) {}

  /// Feeds one byte from the link. Returns kFrame when `frame()` holds a new valid frame,
  /// kError when a frame was dropped (the counters say why), kNone otherwise.
  Event Process(uint8_t byte);

  const Frame& frame() const { return frame_; }
  const FramingCounters& counters() const { return counters_; }
  /// Status of the last dropped frame (kCrcError, kVersionError, ...).
  Status last_error() const { return last_error_; }

 private:
  Event Finish();

  uint8_t* buffer_;
  size_t capacity_;
  size_t length_ = 0;
  size_t raw_bytes_ = 0;
  bool overflowed_ = false;
  CobsDecoder cobs_;
  Frame frame_;
  FramingCounters counters_;
  Status last_error_ = Status::kOk;
};

/// Decoder with its own buffer.
class OwningFrameDecoder : public FrameDecoder {
 public:
  OwningFrameDecoder() : FrameDecoder(storage_, sizeof(storage_)) {}
  OwningFrameDecoder(const OwningFrameDecoder&) = delete;
  OwningFrameDecoder& operator=(const OwningFrameDecoder&) = delete;

 private:
  uint8_t storage_[kMaxPacketSize + kCrcSize];
};

/// Frames a packet (header + body already written in `packet`). Writes the frame, delimiter
/// included, to `out`. Returns the frame length, or kOverflow when `out` is too small and
/// kBadLength when the packet is shorter than a header or longer than kMaxPacketSize.
Result<size_t> EncodeFrame(const uint8_t* packet, size_t packet_size, uint8_t* out,
                           size_t out_capacity);

/// As EncodeFrame, for a packet in a buffer with kCrcSize spare bytes after it: the CRC is
/// appended in place, which saves copying the packet.
Result<size_t> EncodeFrameInPlace(uint8_t* packet, size_t packet_size, uint8_t* out,
                                  size_t out_capacity);

}  // namespace palpa::protocol
