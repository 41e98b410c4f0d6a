// The link's reader thread: frames from the board into the session, the sender's answers, stream
// acknowledgements and telemetry; a board reset or a lost link abandons what was in flight.
#include <chrono>

#include "palpa/host/link.h"

namespace palpa::host {

void Link::ReaderLoop() {
  pp::OwningFrameDecoder decoder;
  uint8_t buffer[4096];
  {
    std::lock_guard<std::mutex> lock(mutex_);
    SendHello();
  }
  while (true) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    const auto n = transport_->Read(buffer, sizeof(buffer), 5);
    if (!n.ok() && n.status == Status::kDisconnected) {
      if (!TransportLost()) return;
      decoder.Process(pp::kFrameDelimiter);  // a frame cut by the loss is not continued
      continue;
    }
    const double now = SteadySeconds();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!n.ok()) continue;
    for (size_t i = 0; i < n.value; ++i) {
      const auto event = decoder.Process(buffer[i]);
      if (event == pp::FrameDecoder::Event::kFrame) OnFrame(decoder.frame(), now);
      if (event == pp::FrameDecoder::Event::kError) ++counters_.framing_errors;
    }
    Service(now);
  }
}

bool Link::TransportLost() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.transport_lost;
    // Reopened only for a board this host still means to hold: not after its own Close, nor once
    // another host holds the board (it took the session over, or a Hello of ours was told busy).
    const bool reopen =
        options_.reopen && !closed_ && (session_.open() || (hello_wanted_ && busy_since_s_ < 0));
    events_.push_back(
        "the link to " + description_ +
        (reopen ? " was lost (unplugged?); reopening it once it is back" : " closed"));
    OnBoardReset("link lost");
    hello_wanted_ = false;
    if (!reopen) {
      stop_ = true;
      changed_.notify_all();
      queue_changed_.notify_all();
      return false;
    }
    reopening_ = true;
  }
  {
    // Released at once, so the device can come back under the same name (a tty, a hidraw node).
    std::lock_guard<std::mutex> lock(write_mutex_);
    transport_.reset();
  }
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (changed_.wait_for(lock, std::chrono::milliseconds(options_.reopen_interval_ms),
                            [&] { return stop_ || closed_; })) {
        stop_ = true;  // closed while the board was away: nothing more to read
        reopening_ = false;
        changed_.notify_all();
        queue_changed_.notify_all();
        return false;
      }
    }
    auto reopened = options_.reopen();
    if (!reopened.ok()) continue;
    {
      std::lock_guard<std::mutex> lock(write_mutex_);
      transport_ = std::move(reopened.value);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.reopens;
    reopening_ = false;
    events_.push_back("reopened " + description_ + "; opening a new session");
    hello_wanted_ = !closed_;  // a Close while the board was being reopened
    hello_sent_s_ = -1;
    SendHello();
    return true;
  }
}

void Link::Service(double now) {  // mutex_ held
  if (!session_.open()) {
    SendHello();
    return;
  }
  sender_.Transmit(Micros(now), [this](const uint8_t* f, size_t n) { WriteFrame(f, n); });
  counters_.retransmissions = sender_.counters().retransmissions;
  for (Stream* s : {&setpoints_, &targets_}) {
    const bool applied =
        s->applied == s->generation || pp::GenerationNewer(s->applied, s->generation);
    if (s->active && !applied && s->refused_generation != s->generation &&
        now - s->sent_s >= options_.stream_resend_ms / 1000.0) {
      WriteFrame(s->frame.data(), s->frame.size());
      s->sent_s = now;
    }
  }
}

void Link::EndSession(const std::string& why, bool reconnect) {  // mutex_ held
  sender_.AbandonAll([&](const pp::CommandOutcome& o) {
    auto it = pending_.find(o.cookie);
    if (it != pending_.end()) {
      it->second.done = true;
      it->second.result = CommandResult{
          Status::kOutcomeUnknown, 0, 0, {}, "the session ended while this command was in flight"};
      host_timeout_.OnUnknown(o.cookie);
      ++counters_.outcome_unknown;
    }
  });
  if (session_.open() && !closed_) events_.push_back(why);
  session_end_ = why;
  session_.Close();
  setpoints_.active = targets_.active = false;
  hello_sent_s_ = -1;
  hello_wanted_ = reconnect && options_.reconnect && !closed_;
  changed_.notify_all();
}

void Link::OnBoardReset(const std::string& why) {  // mutex_ held
  size_t unknown = 0;
  sender_.AbandonAll([&](const pp::CommandOutcome& o) {
    auto it = pending_.find(o.cookie);
    if (it != pending_.end()) {
      it->second.done = true;
      it->second.result = CommandResult{
          Status::kOutcomeUnknown, 0, 0, {}, "the board reset while this command was in flight"};
      host_timeout_.OnUnknown(o.cookie);
    }
    ++unknown;
  });
  counters_.outcome_unknown += unknown;
  if (session_.open()) {
    ++counters_.board_resets;
    events_.push_back(why + ": " + std::to_string(unknown) +
                      " command(s) in flight have an unknown outcome");
  }
  session_end_ = why;
  session_.Close();
  // Streams are not replayed into a new session: the application decides what to actuate.
  setpoints_.active = targets_.active = false;
  hello_sent_s_ = -1;
  hello_wanted_ = options_.reconnect && !closed_;
  changed_.notify_all();
}

void Link::OnFrame(const pp::Frame& frame, double now) {  // mutex_ held
  ++counters_.frames;
  if ((frame.header.flags & pp::flags::kFromBoard) == 0) return;  // an echo of our own frame
  last_board_frame_s_ = now;
  pp::DispatchFrame(frame, [&](const auto& m, const pp::Header& h) {
    using M = std::decay_t<decltype(m)>;
    if constexpr (std::is_same_v<M, pp::HelloReply>) {
      OnHelloReply(m);
    } else if constexpr (requires { m.boot_nonce; }) {
      if constexpr (std::is_same_v<M, pp::Nack>) {
        if (OnHelloBusy(m, now)) return;
      }
      if (!session_.open()) return;
      if (session_.CheckBootNonce(m.boot_nonce) == pp::HostSession::BootCheck::kReset) {
        OnBoardReset("the board restarted");
        return;
      }
      if constexpr (std::is_same_v<M, pp::Telemetry>) {
        OnTelemetry(m, now);
        return;
      }
      if constexpr (std::is_same_v<M, pp::Ack>) OnUnsequencedAck(m);
      if constexpr (std::is_same_v<M, pp::Nack>) {
        if (OnSessionNack(m, h)) return;
      }
      if ((h.flags & pp::flags::kReliable) == 0) return;
      Status status = Status::kOk;
      uint32_t detail = 0;
      if constexpr (std::is_same_v<M, pp::Nack>) {
        status = m.status;
        detail = m.detail;
      }
      const bool report = !std::is_same_v<M, pp::Ack> && !std::is_same_v<M, pp::Nack>;
      OnCommandAnswer(frame, h.seq, status, detail, report, now);
    }
  });
}

void Link::OnHelloReply(const pp::HelloReply& m) {  // mutex_ held
  if (session_.TakenOverBy(m)) {  // our board gave another host a session: ours is over
    EndSession("another host opened a session with the board (Hello nonce " +
                   std::to_string(m.host_nonce) + "): this host no longer holds it",
               false);
    return;
  }
  if (session_.OnHelloReply(m) == Status::kStale) return;
  busy_since_s_ = -1;
  hello_wanted_ = false;
  host_timeout_.OnSession(m.host_timeout_us, m.time_scale);
  // The board answers within a few ticks: cap the back-off at 0.5 s so a command that lost
  // several retransmissions in a row still completes well inside the command timeout.
  sender_.Configure(pp::SenderConfig{pp::kMaxWindow, m.rx_buffer_bytes, 50000, 2000, 500000});
  if (!session_.catalog_matches()) {
    char text[200];
    session_.DescribeVersions(text, sizeof(text));
    events_.push_back(std::string("catalog mismatch, only flashing is possible: ") + text);
  }
  changed_.notify_all();
}

bool Link::OnHelloBusy(const pp::Nack& m, double now) {  // mutex_ held
  // Our Hello refused: another host's session is alive. Retried until it has been busy for
  // longer than a silent host's session lasts (Open).
  if (m.refused_type != static_cast<uint8_t>(pp::MessageType::kHello) ||
      m.status != Status::kBusy || session_.open() || !hello_wanted_) {
    return false;
  }
  if (busy_since_s_ < 0) busy_since_s_ = now;
  busy_timeout_us_ = m.detail;
  changed_.notify_all();
  return true;
}

void Link::OnUnsequencedAck(const pp::Ack& m) {  // mutex_ held
  if (m.acked_type == static_cast<uint8_t>(pp::MessageType::kEStop)) estop_acked_ = true;
  if (m.acked_type == static_cast<uint8_t>(pp::MessageType::kClose)) close_answered_ = true;
  if (m.acked_type == static_cast<uint8_t>(pp::MessageType::kRelease)) {
    release_status_ = Status::kOk;
    release_answered_ = true;
  }
  changed_.notify_all();
}

bool Link::OnSessionNack(const pp::Nack& m, const pp::Header& h) {  // mutex_ held
  // A Close is heard whatever the answer: no_session (already over) or a bootloader's
  // unsupported (it keeps no session to end). So is a Release refused by a bootloader, whose
  // lines are always safe.
  if (m.refused_type == static_cast<uint8_t>(pp::MessageType::kClose)) {
    close_answered_ = true;
    changed_.notify_all();
    return true;
  }
  if (m.refused_type == static_cast<uint8_t>(pp::MessageType::kRelease)) {
    release_status_ = m.status == Status::kUnsupported ? Status::kOk : m.status;
    release_answered_ = true;
    changed_.notify_all();
  }
  if (m.status == Status::kNoSession) {  // the board holds no session of ours any more
    EndSession(
        "the board ended the session: it heard nothing fresh from this host within its "
        "host-silence timeout",
        true);
    return true;
  }
  if ((h.flags & pp::flags::kReliable) != 0) return false;
  // A refused stream message.
  Stream* s =
      m.refused_type == static_cast<uint8_t>(pp::MessageType::kSetLineSetpoints)   ? &setpoints_
      : m.refused_type == static_cast<uint8_t>(pp::MessageType::kSetFingerTargets) ? &targets_
                                                                                   : nullptr;
  if (s != nullptr) {
    s->refused = m.status;
    s->refused_detail = m.detail;
    s->refused_generation = s->generation;
    changed_.notify_all();
  }
  return true;
}

void Link::OnCommandAnswer(const pp::Frame& frame, uint8_t seq, Status status, uint32_t detail,
                           bool report, double now) {  // mutex_ held
  sender_.OnAnswer(seq, status, detail, Micros(now), [&](const pp::CommandOutcome& o) {
    auto it = pending_.find(o.cookie);
    if (it == pending_.end()) return;
    it->second.done = true;
    it->second.result = CommandResult{o.status, o.detail, 0, {}, {}};
    if (o.status == Status::kOk)
      host_timeout_.OnApplied(o.cookie);
    else
      host_timeout_.OnRefused(o.cookie);
    if (report && o.seq == seq) {
      it->second.result.reply_type = frame.header.type;
      it->second.result.reply_body.assign(frame.body, frame.body + frame.body_size);
    }
  });
  changed_.notify_all();
}

}  // namespace palpa::host
