// SHA-256 (FIPS 180-4), streaming and freestanding: the firmware image hash the bootloader, the
// board's update engine and the host's flasher all compute.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "palpa/protocol/sha2_blocks.h"

namespace palpa::protocol {

using Sha256Digest = std::array<uint8_t, 32>;

class Sha256Hasher {
 public:
  Sha256Hasher() { Reset(); }
  void Reset();
  void Update(const uint8_t* data, size_t size);
  /// The digest of everything since Reset(); the object must be Reset() before reuse.
  Sha256Digest Finish();

 private:
  void Block(const uint8_t* block);
  // First, at the hasher's own address: the buffering then needs no second base register (the
  // smaller code on the Cortex-M4; SHA-512's longer Block is the smaller with its state first).
  Sha2Blocks<64, 8> blocks_;
  uint32_t state_[8];
};

inline Sha256Digest Sha256Of(const uint8_t* data, size_t size) {
  Sha256Hasher h;
  h.Update(data, size);
  return h.Finish();
}

}  // namespace palpa::protocol
