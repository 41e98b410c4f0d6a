// Host side of the reliable channel: go-back-N window, cumulative acks, adaptive retransmission.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/sequence.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {

struct SenderConfig {
  uint8_t window = kMaxWindow;         ///< ≤ kMaxWindow
  uint32_t max_bytes_in_flight = 512;  ///< the board's receive buffer (HelloReply)
  uint32_t initial_rto_us = 100000;    ///< before the first round-trip sample
  uint32_t min_rto_us = 2000;
  uint32_t max_rto_us = 2000000;
};

/// The final word on one reliable command.
struct CommandOutcome {
  uint32_t cookie = 0;  ///< the caller's tag from Submit
  uint8_t seq = 0;
  uint8_t type = 0;
  Status status = Status::kOk;  ///< kOk, the Nack status, or kOutcomeUnknown
  uint32_t detail = 0;
};

struct SenderCounters {
  uint32_t submitted = 0;
  uint32_t transmissions = 0;
  uint32_t retransmissions = 0;
  uint32_t timeouts = 0;
  uint32_t fast_retransmits = 0;
};

class ReliableSender {
 public:
  explicit ReliableSender(SenderConfig config = {}) { Configure(config); }

  /// Applies new limits (e.g. after HelloReply reports the board's receive buffer).
  void Configure(SenderConfig config);

  /// Starts a session at `initial_seq`; anything pending must have been abandoned first.
  void Reset(uint8_t initial_seq);

  /// Queues `m` with the next seq. Returns the seq, or kWindowFull when the window or the
  /// bytes-in-flight budget is exhausted (retry after answers arrive), or the encode error.
  template <class M>
  Result<uint8_t> Submit(const M& m, uint32_t cookie, FieldError* error = nullptr) {
    if (pending() >= config_.window) return Status::kWindowFull;
    Pending& slot = slots_[next_seq_ % kMaxWindow];  // free: pending() < window
    const Result<size_t> size =
        EncodePacket(m, next_seq_, flags::kReliable, slot.packet, sizeof(slot.packet), error);
    if (!size.ok()) return size.status;
    if (pending() > 0 && BytesInFlight() + FramedSize(size.value) > config_.max_bytes_in_flight) {
      return Status::kWindowFull;
    }
    slot.packet_size = static_cast<uint16_t>(size.value);
    slot.seq = next_seq_;
    slot.type = static_cast<uint8_t>(M::kInfo.type);
    slot.cookie = cookie;
    slot.sent_us = 0;
    slot.transmissions = 0;
    slot.consumed = slot.answered = slot.due = false;
    slot.in_use = true;
    ++next_seq_;
    ++counters_.submitted;
    return slot.seq;
  }

  /// As Submit, for a body already encoded (the host library encodes before it locks).
  Result<uint8_t> SubmitEncoded(uint8_t type, const uint8_t* body, size_t body_size,
                                uint32_t cookie) {
    if (pending() >= config_.window) return Status::kWindowFull;
    if (body_size > kMaxBodySize) return Status::kOverflow;
    if (pending() > 0 &&
        BytesInFlight() + FramedSize(kHeaderSize + body_size) > config_.max_bytes_in_flight) {
      return Status::kWindowFull;
    }
    Pending& slot = slots_[next_seq_ % kMaxWindow];
    WriteHeader(Header{kProtocolVersion, type, next_seq_, flags::kReliable}, slot.packet);
    for (size_t i = 0; i < body_size; ++i) slot.packet[kHeaderSize + i] = body[i];
    slot.packet_size = static_cast<uint16_t>(kHeaderSize + body_size);
    slot.seq = next_seq_;
    slot.type = type;
    slot.cookie = cookie;
    slot.sent_us = 0;
    slot.transmissions = 0;
    slot.consumed = slot.answered = slot.due = false;
    slot.in_use = true;
    ++next_seq_;
    ++counters_.submitted;
    return slot.seq;
  }

  /// The board answered `seq` (Ack, Nack or a report). A Nack with kSeqGap means "everything
  /// before `detail` arrived; resend from there". Calls on_outcome(CommandOutcome) for every
  /// command whose answer is now known.
  template <class F>
  void OnAnswer(uint8_t seq, Status status, uint32_t detail, uint64_t now_us, F&& on_outcome) {
    if (status == Status::kSeqGap) {
      MarkConsumedBefore(static_cast<uint8_t>(detail));
      ScheduleFastRetransmit(static_cast<uint8_t>(detail));
    } else {
      const int offset = SeqDistance(seq, base_seq_);
      if (offset < 0 || offset >= static_cast<int>(pending())) return;  // stale or unknown
      Pending& p = slots_[seq % kMaxWindow];
      if (!p.answered) {
        MarkConsumedBefore(seq);
        p.consumed = p.answered = true;
        // Karn: only an answer to a command sent once is a round-trip sample, and only such an
        // answer drops the back-off. Dropping it on any answer kept the timeout below the
        // queueing delay of a full window on a slow link: every command went out twice.
        if (p.transmissions == 1) {
          SampleRoundTrip(now_us - p.sent_us);
          rto_us_ = base_rto_us_;
        }
        on_outcome(CommandOutcome{p.cookie, p.seq, p.type, status, detail});
        // Earlier commands were consumed but their answers lost: ask again, the board replays.
        for (uint8_t s = base_seq_; s != seq; ++s) {
          if (!slots_[s % kMaxWindow].answered) slots_[s % kMaxWindow].due = true;
        }
      }
    }
    while (pending() > 0 && slots_[base_seq_ % kMaxWindow].answered) {
      slots_[base_seq_ % kMaxWindow].in_use = false;
      ++base_seq_;
    }
  }

  /// Sends what is due at now_us: new commands, and on timeout everything unanswered
  /// (go-back-N, RTO doubled). send(const uint8_t* frame, size_t size). Returns frames sent.
  template <class F>
  size_t Transmit(uint64_t now_us, F&& send) {
    MarkTimedOut(now_us);
    size_t sent = 0;
    for (uint8_t s = base_seq_; s != next_seq_; ++s) {
      Pending& p = slots_[s % kMaxWindow];
      if (p.answered || !(p.due || p.transmissions == 0)) continue;
      uint8_t frame[kMaxFrameSize];
      if (p.transmissions > 0) {
        p.packet[3] |= flags::kRetransmit;
        ++counters_.retransmissions;
      }
      const Result<size_t> size = EncodeFrame(p.packet, p.packet_size, frame, sizeof(frame));
      if (!size.ok()) continue;  // cannot happen: the packet was encoded within limits
      send(static_cast<const uint8_t*>(frame), size.value);
      p.sent_us = now_us;
      p.due = false;
      if (p.transmissions < 255) ++p.transmissions;
      ++counters_.transmissions;
      ++sent;
    }
    return sent;
  }

  /// The session is gone (board reset, link lost): every unanswered command's outcome is unknown.
  template <class F>
  void AbandonAll(F&& on_outcome) {
    for (uint8_t s = base_seq_; s != next_seq_; ++s) {
      Pending& p = slots_[s % kMaxWindow];
      if (!p.answered) {
        on_outcome(CommandOutcome{p.cookie, p.seq, p.type, Status::kOutcomeUnknown, 0});
      }
      p.in_use = false;
    }
    base_seq_ = next_seq_;
  }

  /// Earliest time at which Transmit has something to do (UINT64_MAX when idle).
  uint64_t NextDeadline() const;

  size_t pending() const { return static_cast<uint8_t>(next_seq_ - base_seq_); }
  /// Whether a command with a body of `body_size` bytes fits the window and the bytes in flight
  /// now.
  bool HasRoomFor(size_t body_size) const {
    return pending() == 0 ||
           (pending() < config_.window &&
            BytesInFlight() + FramedSize(kHeaderSize + body_size) <= config_.max_bytes_in_flight);
  }
  uint8_t next_seq() const { return next_seq_; }
  uint32_t rto_us() const { return rto_us_; }
  /// The timeout the round trips measured call for, without the back-off of timeouts since.
  uint32_t base_rto_us() const { return base_rto_us_; }
  uint32_t BytesInFlight() const;
  const SenderCounters& counters() const { return counters_; }

 private:
  struct Pending {
    uint8_t packet[kMaxPacketSize] = {};
    uint16_t packet_size = 0;
    uint8_t seq = 0;
    uint8_t type = 0;
    uint32_t cookie = 0;
    uint64_t sent_us = 0;
    uint8_t transmissions = 0;
    bool consumed = false;  ///< the board has passed this seq (no longer in its buffer)
    bool answered = false;
    bool due = false;
    bool in_use = false;
  };

  static constexpr uint32_t FramedSize(size_t packet_size) {
    return static_cast<uint32_t>(CobsMaxEncodedSize(packet_size + kCrcSize) + 1);
  }
  void MarkConsumedBefore(uint8_t seq);
  void ScheduleFastRetransmit(uint8_t from_seq);
  void MarkTimedOut(uint64_t now_us);
  void SampleRoundTrip(uint64_t rtt_us);

  SenderConfig config_{};
  std::array<Pending, kMaxWindow> slots_{};
  uint8_t base_seq_ = 0;
  uint8_t next_seq_ = 0;
  uint32_t rto_us_ = 0;
  uint32_t base_rto_us_ = 0;  ///< RTO before exponential back-off
  int64_t srtt_us_ = -1;      ///< -1: no sample yet
  int64_t rttvar_us_ = 0;
  SenderCounters counters_{};
};

}  // namespace palpa::protocol
