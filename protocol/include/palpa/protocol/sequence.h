// Wrap-aware comparison of u8 sequence numbers and u32 generations, and the latest-wins gate.
#pragma once

#include <cstdint>

namespace palpa::protocol {

/// Go-back-N window: at most this many reliable commands unanswered.
inline constexpr uint8_t kMaxWindow = 16;

/// a - b as a signed distance on the u8 circle (-128..127).
constexpr int SeqDistance(uint8_t a, uint8_t b) { return static_cast<int8_t>(a - b); }

/// True when generation a is newer than b on the u32 circle.
constexpr bool GenerationNewer(uint32_t a, uint32_t b) { return static_cast<int32_t>(a - b) > 0; }

/// Latest-wins rule for one stream: applies a generation only if newer than the last applied.
class GenerationGate {
 public:
  /// Returns true (and records it) when `generation` should be applied.
  bool Accept(uint32_t generation) {
    if (has_applied_ && !GenerationNewer(generation, applied_)) {
      ++dropped_;
      return false;
    }
    applied_ = generation;
    has_applied_ = true;
    return true;
  }
  /// Would Accept() apply this generation? (Lets a receiver validate before committing.)
  bool WouldAccept(uint32_t generation) const {
    return !has_applied_ || GenerationNewer(generation, applied_);
  }
  /// Forget history: a new session starts its streams afresh.
  void Reset() {
    has_applied_ = false;
    applied_ = 0;
  }
  bool has_applied() const { return has_applied_; }
  uint32_t applied() const { return applied_; }
  uint32_t dropped() const { return dropped_; }

 private:
  uint32_t applied_ = 0;
  uint32_t dropped_ = 0;
  bool has_applied_ = false;
};

}  // namespace palpa::protocol
