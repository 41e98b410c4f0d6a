// Wire constants and the 4-byte packet header: the only copy of these numbers.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/status.h"

namespace palpa::protocol {

inline constexpr uint8_t kProtocolVersion = 1;
inline constexpr size_t kHeaderSize = 4;
inline constexpr size_t kMaxPacketSize = 256;  ///< header + body, without the CRC
inline constexpr size_t kMaxBodySize = kMaxPacketSize - kHeaderSize;
inline constexpr size_t kCrcSize = 4;
inline constexpr uint8_t kFrameDelimiter = 0x00;

/// COBS adds one code byte per started run of 254 data bytes.
constexpr size_t CobsMaxEncodedSize(size_t raw) { return raw + raw / 254 + 1; }

/// Largest frame on the wire: COBS(packet ‖ crc) ‖ 0x00.
inline constexpr size_t kMaxFrameSize = CobsMaxEncodedSize(kMaxPacketSize + kCrcSize) + 1;

/// Header flag bits (byte 3). Bits 4..7 are reserved: a frame with any of them set is rejected.
namespace flags {
inline constexpr uint8_t kReliable = 1u << 0;    ///< seq is a reliable-channel sequence number
inline constexpr uint8_t kRetransmit = 1u << 1;  ///< sender repeats an earlier frame
inline constexpr uint8_t kFromBoard = 1u << 2;   ///< frame sent by the board (loopback check)
inline constexpr uint8_t kFaulted = 1u << 3;     ///< board frames: a fault is latched
inline constexpr uint8_t kReservedMask = 0xF0u;
}  // namespace flags

struct Header {
  uint8_t version = kProtocolVersion;
  uint8_t type = 0;
  uint8_t seq = 0;
  uint8_t flags = 0;
};

inline void WriteHeader(const Header& h, uint8_t* out) {
  out[0] = h.version;
  out[1] = h.type;
  out[2] = h.seq;
  out[3] = h.flags;
}

/// Parses and checks a header: version must be 1 and no reserved flag may be set.
inline Status ReadHeader(const uint8_t* in, size_t size, Header& h) {
  if (size < kHeaderSize) return Status::kBadLength;
  h = Header{in[0], in[1], in[2], in[3]};
  if (h.version != kProtocolVersion) return Status::kVersionError;
  if ((h.flags & flags::kReservedMask) != 0) return Status::kReservedFlags;
  return Status::kOk;
}

}  // namespace palpa::protocol
