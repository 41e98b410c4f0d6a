// CRC-32 (IEEE 802.3 / zlib: reflected 0x04C11DB7, init and xor-out 0xFFFFFFFF).
#pragma once

#include <cstddef>
#include <cstdint>

namespace palpa::protocol {

/// Continues a CRC-32: pass the previous result (0 to start). Crc32Update(Crc32Update(0,a),b)
/// equals the CRC of a‖b, as zlib.crc32 does.
uint32_t Crc32Update(uint32_t crc, const uint8_t* data, size_t size);

inline uint32_t Crc32(const uint8_t* data, size_t size) { return Crc32Update(0, data, size); }

}  // namespace palpa::protocol
