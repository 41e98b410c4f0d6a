// SHA-256 (FIPS 180-4), streaming and freestanding: the firmware image hash the bootloader, the
// board's update engine and the host's flasher all compute.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

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
  uint32_t state_[8];
  uint8_t buffer_[64];
  uint64_t length_ = 0;  ///< bytes hashed
  size_t buffered_ = 0;
};

inline Sha256Digest Sha256Of(const uint8_t* data, size_t size) {
  Sha256Hasher h;
  h.Update(data, size);
  return h.Finish();
}

}  // namespace palpa::protocol
