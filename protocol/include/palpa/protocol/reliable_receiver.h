// Board side of the reliable channel: apply the expected seq only, replay duplicates, signal gaps.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/sequence.h"
#include "palpa/protocol/status.h"

namespace palpa::protocol {

/// The answer the board gave to one reliable command, kept so a duplicate gets the same answer.
struct CachedOutcome {
  uint8_t seq = 0;
  uint8_t type = 0;
  Status status = Status::kOk;
  uint32_t detail = 0;
  bool data_reply = false;  ///< answered with a report (queries): re-run it, it is read-only
  bool valid = false;
};

class ReliableReceiver {
 public:
  enum class Verdict : uint8_t {
    kApply,      ///< the expected seq: apply, then call Complete()
    kDuplicate,  ///< already applied: answer with *cached
    kGap,        ///< ahead of expected: answer Nack(seq_gap, detail = expected())
    kIgnore,     ///< out of the window, or a gap already signalled for this expected seq
  };

  /// Starts a session: `initial_seq` is the first seq the host will send.
  void Reset(uint8_t initial_seq) {
    expected_ = initial_seq;
    gap_signalled_ = false;
    for (CachedOutcome& c : cache_) c = CachedOutcome{};
  }

  Verdict Classify(uint8_t seq, const CachedOutcome** cached) {
    const int distance = SeqDistance(seq, expected_);
    if (distance == 0) return Verdict::kApply;
    if (distance < 0 && distance >= -static_cast<int>(kMaxWindow)) {
      const CachedOutcome& c = cache_[seq % kMaxWindow];
      if (c.valid && c.seq == seq) {
        *cached = &c;
        return Verdict::kDuplicate;
      }
      return Verdict::kIgnore;
    }
    if (distance > 0 && distance < static_cast<int>(kMaxWindow)) {
      if (gap_signalled_) return Verdict::kIgnore;
      gap_signalled_ = true;
      return Verdict::kGap;
    }
    return Verdict::kIgnore;
  }

  /// Records the answer to the expected command and moves on to the next seq.
  void Complete(uint8_t type, Status status, uint32_t detail, bool data_reply) {
    cache_[expected_ % kMaxWindow] =
        CachedOutcome{expected_, type, status, detail, data_reply, true};
    ++expected_;
    gap_signalled_ = false;
  }

  uint8_t expected() const { return expected_; }

 private:
  std::array<CachedOutcome, kMaxWindow> cache_{};
  uint8_t expected_ = 0;
  bool gap_signalled_ = false;
};

}  // namespace palpa::protocol
