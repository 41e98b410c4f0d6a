// Test board, test host and lossy channel for the reliable-channel and session tests.
#include "link_harness.h"

namespace palpa::testing {

void LossyChannel::Send(const uint8_t* frame, size_t size, uint64_t now_us) {
  if (Chance(faults_.drop)) return;
  const int copies = Chance(faults_.duplicate) ? 2 : 1;
  for (int c = 0; c < copies; ++c) {
    std::vector<uint8_t> bytes;
    for (size_t i = 0; i < size; ++i) {
      if (!Chance(faults_.byte_loss)) bytes.push_back(frame[i]);
    }
    if (!bytes.empty() && Chance(faults_.corrupt)) {
      bytes[rng_() % bytes.size()] ^= static_cast<uint8_t>(1u << (rng_() % 8));
    }
    const uint64_t jitter = faults_.jitter_us ? rng_() % faults_.jitter_us : 0;
    queue_.emplace(now_us + faults_.latency_us + jitter, std::move(bytes));
  }
}

std::vector<uint8_t> LossyChannel::Deliver(uint64_t now_us) {
  std::vector<uint8_t> out;
  while (!queue_.empty() && queue_.begin()->first <= now_us) {
    out.insert(out.end(), queue_.begin()->second.begin(), queue_.begin()->second.end());
    queue_.erase(queue_.begin());
  }
  return out;
}

TestBoard::TestBoard(uint32_t catalog_hash, uint16_t rx_buffer_bytes, uint32_t seed)
    : catalog_hash_(catalog_hash), rx_buffer_bytes_(rx_buffer_bytes), rng_(seed) {
  Reboot();
}

void TestBoard::Reboot() { session_ = pp::BoardSession(static_cast<uint32_t>(rng_())); }

template <class M>
void TestBoard::Reply(const M& m, uint8_t seq, uint8_t flags,
                      std::vector<std::vector<uint8_t>>& out) {
  std::vector<uint8_t> frame(pp::kMaxFrameSize);
  const auto n =
      pp::EncodeMessageFrame(m, seq, flags | pp::flags::kFromBoard, frame.data(), frame.size());
  frame.resize(n.value);
  out.push_back(std::move(frame));
}

void TestBoard::Receive(const std::vector<uint8_t>& bytes, std::vector<std::vector<uint8_t>>& out) {
  for (uint8_t b : bytes) {
    if (decoder_.Process(b) == pp::FrameDecoder::Event::kFrame) Handle(decoder_.frame(), out);
  }
}

void TestBoard::Handle(const pp::Frame& frame, std::vector<std::vector<uint8_t>>& out) {
  const uint8_t type = frame.header.type;
  const uint8_t seq = frame.header.seq;
  const bool reliable = (frame.header.flags & pp::flags::kReliable) != 0;
  const uint8_t answer_flags = reliable ? pp::flags::kReliable : 0;
  const uint32_t boot_nonce = session_.boot_nonce();
  pp::ReliableReceiver& receiver = session_.receiver();
  if (session_.Admit(type) != pp::Status::kOk) {
    Reply(pp::Nack{boot_nonce, type, pp::Status::kNoSession, 0}, seq, answer_flags, out);
    return;
  }
  if (reliable) {
    const pp::CachedOutcome* cached = nullptr;
    switch (receiver.Classify(seq, &cached)) {
      case pp::ReliableReceiver::Verdict::kApply:
        break;
      case pp::ReliableReceiver::Verdict::kDuplicate:
        if (cached->status == pp::Status::kOk) {
          Reply(pp::Ack{boot_nonce, cached->type}, seq, pp::flags::kReliable, out);
        } else {
          Reply(pp::Nack{boot_nonce, cached->type, cached->status, cached->detail}, seq,
                pp::flags::kReliable, out);
        }
        return;
      case pp::ReliableReceiver::Verdict::kGap:
        Reply(pp::Nack{boot_nonce, type, pp::Status::kSeqGap, receiver.expected()}, seq,
              pp::flags::kReliable, out);
        return;
      case pp::ReliableReceiver::Verdict::kIgnore:
        return;
    }
  }
  pp::Status status = pp::Status::kOk;
  const pp::Status decoded = pp::DispatchFrame(frame, [&](const auto& m, const pp::Header&) {
    using M = std::decay_t<decltype(m)>;
    if constexpr (std::is_same_v<M, pp::Hello>) {
      const auto verdict = session_.OnHello(m, 0);  // a repeated Hello is only answered again
      if (verdict == pp::BoardSession::HelloVerdict::kBusy) return;
      if (verdict == pp::BoardSession::HelloVerdict::kOpened) ++sessions;
      pp::HelloReply r{};
      r.host_nonce = m.host_nonce;
      r.boot_nonce = boot_nonce;
      r.catalog_hash = catalog_hash_;
      r.rx_buffer_bytes = rx_buffer_bytes_;
      r.firmware_minor = 1;
      Reply(r, 0, 0, out);
    } else if constexpr (std::is_same_v<M, pp::ClearFault>) {
      if (m.mask == 0) {
        status = pp::Status::kOutOfRange;  // an "out of limit" command: Nacked, not applied
      } else {
        applied.push_back(Applied{boot_nonce, m.mask});
      }
    } else if constexpr (std::is_same_v<M, pp::Heartbeat>) {
      if (session_.Owns(m.session)) session_.heartbeat().Accept(m.generation);
    } else if constexpr (std::is_same_v<M, pp::EStop>) {
      Reply(pp::Ack{boot_nonce, type}, seq, 0, out);
    } else if constexpr (std::is_same_v<M, pp::SetLineSetpoints> ||
                         std::is_same_v<M, pp::SetFingerTargets>) {
      ++stream_frames;
      if constexpr (std::is_same_v<M, pp::SetLineSetpoints>) {
        for (uint8_t i = 0; i < m.entry_count; ++i) {  // Nacked unsequenced, detail the entry
          if (m.entries[i].line >= kLines) {
            Reply(pp::Nack{boot_nonce, type, pp::Status::kNotFound, i}, seq, 0, out);
            return;
          }
        }
      }
    } else if constexpr (std::is_same_v<M, pp::Close> || std::is_same_v<M, pp::Release>) {
      if constexpr (std::is_same_v<M, pp::Release>) ++releases;
      if (recovery) {
        Reply(pp::Nack{boot_nonce, type, pp::Status::kUnsupported, 0}, seq, 0, out);
        return;
      }
      if (!session_.Owns(m.session)) {
        Reply(pp::Nack{boot_nonce, type, pp::Status::kNoSession, 0}, seq, 0, out);
        return;
      }
      if constexpr (std::is_same_v<M, pp::Close>) {
        session_.End();
        ++closes;
      }
      Reply(pp::Ack{boot_nonce, type}, seq, 0, out);
    }
  });
  if (type == static_cast<uint8_t>(pp::MessageType::kHello)) return;
  if (decoded != pp::Status::kOk) status = decoded;
  if (!reliable) return;
  if (type == static_cast<uint8_t>(pp::MessageType::kUpdateQuery) && status == pp::Status::kOk) {
    receiver.Complete(type, status, 0, true);
    Reply(pp::UpdateStatus{boot_nonce, 1, 1234, {}, false}, seq, pp::flags::kReliable, out);
    return;
  }
  receiver.Complete(type, status, 0, false);
  if (status == pp::Status::kOk) {
    Reply(pp::Ack{boot_nonce, type}, seq, pp::flags::kReliable, out);
  } else {
    Reply(pp::Nack{boot_nonce, type, status, 0}, seq, pp::flags::kReliable, out);
  }
}

TestHost::TestHost(uint32_t catalog_hash, uint32_t seed, uint8_t initial_seq)
    : session(catalog_hash), rng_(seed), next_initial_seq_(initial_seq) {}

void TestHost::QueueCommands(uint32_t first_id, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i) queue_.push_back(first_id + i);
}

void TestHost::OnFrame(const pp::Frame& frame) {
  pp::DispatchFrame(frame, [&](const auto& m, const pp::Header& h) {
    using M = std::decay_t<decltype(m)>;
    if constexpr (std::is_same_v<M, pp::HelloReply>) {
      const pp::Status s = session.OnHelloReply(m);
      if (s == pp::Status::kStale) return;
      hello_in_flight_ = false;
      sender.Configure(pp::SenderConfig{pp::kMaxWindow, m.rx_buffer_bytes, 20000, 1000, 500000});
    } else if constexpr (requires { m.boot_nonce; }) {
      if (!session.open()) return;
      if (session.CheckBootNonce(m.boot_nonce) == pp::HostSession::BootCheck::kReset) {
        ++resets_seen;
        sender.AbandonAll([&](const pp::CommandOutcome& o) { outcomes[o.cookie] = o.status; });
        session.Close();
        return;
      }
      if ((h.flags & pp::flags::kReliable) == 0) return;
      pp::Status status = pp::Status::kOk;
      uint32_t detail = 0;
      if constexpr (std::is_same_v<M, pp::Nack>) {
        status = m.status;
        detail = m.detail;
      }
      sender.OnAnswer(h.seq, status, detail, now_us_,
                      [&](const pp::CommandOutcome& o) { outcomes[o.cookie] = o.status; });
    }
  });
}

void TestHost::Step(uint64_t now_us, const std::vector<uint8_t>& from_board,
                    const std::function<void(const uint8_t*, size_t)>& send) {
  now_us_ = now_us;
  for (uint8_t b : from_board) {
    if (decoder_.Process(b) == pp::FrameDecoder::Event::kFrame) OnFrame(decoder_.frame());
  }
  if (!session.open()) {
    if (!hello_in_flight_ || now_us - hello_sent_us_ > 50000) {
      // One nonce per session attempt; retries repeat it so the board never resets twice.
      if (!hello_in_flight_) {
        hello_nonce_ = static_cast<uint32_t>(rng_());
        session.BeginHello(hello_nonce_);
        sender.Reset(next_initial_seq_);
      }
      const uint32_t nonce = hello_nonce_;
      uint8_t frame[pp::kMaxFrameSize];
      const auto n =
          pp::EncodeMessageFrame(pp::Hello{nonce, next_initial_seq_}, 0, 0, frame, sizeof(frame));
      send(frame, n.value);
      hello_in_flight_ = true;
      hello_sent_us_ = now_us;
    }
    return;
  }
  while (!queue_.empty()) {
    const auto seq = sender.Submit(pp::ClearFault{queue_.front()}, queue_.front());
    if (!seq.ok()) {
      ++window_full_refusals;
      break;
    }
    submitted_order.push_back(queue_.front());
    queue_.pop_front();
  }
  if (sender.BytesInFlight() > max_bytes_in_flight) max_bytes_in_flight = sender.BytesInFlight();
  sender.Transmit(now_us, send);
}

}  // namespace palpa::testing
