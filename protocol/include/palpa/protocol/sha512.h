// SHA-512 (FIPS 180-4), streaming and freestanding: the hash inside Ed25519 signature checks.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

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
  uint8_t buffer_[128];
  uint64_t length_ = 0;  ///< bytes hashed (messages under 2^61 bytes: the high length word is 0)
  size_t buffered_ = 0;
};

inline Sha512Digest Sha512Of(const uint8_t* data, size_t size) {
  Sha512Hasher h;
  h.Update(data, size);
  return h.Finish();
}

}  // namespace palpa::protocol
