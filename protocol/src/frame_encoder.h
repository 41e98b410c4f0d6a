// The frame encoder's fast path: CRC-32 and COBS in one pass, a word at a time.
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::protocol {

/// Writes COBS(packet ‖ crc32_le(packet)) ‖ 0x00 to `out` and returns its length. `packet` has
/// kCrcSize spare bytes after `packet_size` (the CRC goes there); `out` holds at least
/// CobsMaxEncodedSize(packet_size + kCrcSize) + 1 bytes. Output equals Crc32 then CobsEncode.
size_t EncodeFrameWordwise(uint8_t* packet, size_t packet_size, uint8_t* out);

}  // namespace palpa::protocol
