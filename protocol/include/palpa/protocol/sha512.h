// SHA-512 (FIPS 180-4), streaming and freestanding: the hash inside Ed25519 signature checks.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "palpa/protocol/sha2_blocks.h"

namespace palpa::protocol {

using Sha512Digest = std::array<uint8_t, 64>;

class Sha512Hasher {
 public:
  Sha512Hasher() { Reset(); }
  void Reset();
  void Update(const uint8_t* data, size_t size);
  /// The digest of everything since Reset(); the object must be Reset() before reuse.
  Sha512Digest Finish();

 private:
  void Block(const uint8_t* block);
  uint64_t state_[8];
  Sha2Blocks<128, 16> blocks_;
};

inline Sha512Digest Sha512Of(const uint8_t* data, size_t size) {
  Sha512Hasher h;
  h.Update(data, size);
  return h.Finish();
}

}  // namespace palpa::protocol
