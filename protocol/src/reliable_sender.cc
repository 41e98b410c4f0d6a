// Reliable sender bookkeeping: bytes in flight, retransmission schedule, RFC 6298 round-trip timer.
#include "palpa/protocol/reliable_sender.h"

namespace palpa::protocol {

void ReliableSender::Configure(SenderConfig config) {
  if (config.window == 0 || config.window > kMaxWindow) config.window = kMaxWindow;
  if (config.min_rto_us == 0) config.min_rto_us = 1;
  if (config.max_rto_us < config.min_rto_us) config.max_rto_us = config.min_rto_us;
  config_ = config;
  if (srtt_us_ < 0) base_rto_us_ = rto_us_ = config.initial_rto_us;
}

void ReliableSender::Reset(uint8_t initial_seq) {
  for (Pending& p : slots_) p.in_use = false;
  base_seq_ = next_seq_ = initial_seq;
}

uint32_t ReliableSender::BytesInFlight() const {
  uint32_t bytes = 0;
  for (uint8_t s = base_seq_; s != next_seq_; ++s) {
    const Pending& p = slots_[s % kMaxWindow];
    if (!p.consumed) bytes += FramedSize(p.packet_size);
  }
  return bytes;
}

void ReliableSender::MarkConsumedBefore(uint8_t seq) {
  for (uint8_t s = base_seq_; s != next_seq_ && SeqDistance(s, seq) < 0; ++s) {
    slots_[s % kMaxWindow].consumed = true;
  }
}

void ReliableSender::ScheduleFastRetransmit(uint8_t from_seq) {
  bool any = false;
  for (uint8_t s = base_seq_; s != next_seq_; ++s) {
    Pending& p = slots_[s % kMaxWindow];
    if (SeqDistance(s, from_seq) >= 0 && !p.answered && p.transmissions > 0) {
      p.due = true;
      any = true;
    }
  }
  if (any) ++counters_.fast_retransmits;
}

void ReliableSender::MarkTimedOut(uint64_t now_us) {
  if (pending() == 0) return;
  // The oldest unanswered command decides: go back to it and resend everything unanswered.
  for (uint8_t s = base_seq_; s != next_seq_; ++s) {
    const Pending& p = slots_[s % kMaxWindow];
    if (p.answered || p.transmissions == 0) continue;
    if (now_us - p.sent_us < rto_us_) return;
    for (uint8_t t = s; t != next_seq_; ++t) {
      Pending& q = slots_[t % kMaxWindow];
      if (!q.answered && q.transmissions > 0) q.due = true;
    }
    ++counters_.timeouts;
    const uint64_t backed_off = static_cast<uint64_t>(rto_us_) * 2;
    rto_us_ =
        static_cast<uint32_t>(backed_off > config_.max_rto_us ? config_.max_rto_us : backed_off);
    return;
  }
}

void ReliableSender::SampleRoundTrip(uint64_t rtt_us) {
  const int64_t rtt = static_cast<int64_t>(rtt_us > 60000000u ? 60000000u : rtt_us);
  if (srtt_us_ < 0) {
    srtt_us_ = rtt;
    rttvar_us_ = rtt / 2;
  } else {
    const int64_t error = rtt > srtt_us_ ? rtt - srtt_us_ : srtt_us_ - rtt;
    rttvar_us_ = (3 * rttvar_us_ + error) / 4;
    srtt_us_ = (7 * srtt_us_ + rtt) / 8;
  }
  int64_t rto = srtt_us_ + (4 * rttvar_us_ > 1000 ? 4 * rttvar_us_ : 1000);
  if (rto < config_.min_rto_us) rto = config_.min_rto_us;
  if (rto > config_.max_rto_us) rto = config_.max_rto_us;
  base_rto_us_ = rto_us_ = static_cast<uint32_t>(rto);
}

uint64_t ReliableSender::NextDeadline() const {
  uint64_t deadline = UINT64_MAX;
  for (uint8_t s = base_seq_; s != next_seq_; ++s) {
    const Pending& p = slots_[s % kMaxWindow];
    if (p.answered) continue;
    if (p.transmissions == 0 || p.due) return 0;
    const uint64_t at = p.sent_us + rto_us_;
    if (at < deadline) deadline = at;
  }
  return deadline;
}

}  // namespace palpa::protocol
