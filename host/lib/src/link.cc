// The link: commands, streams and the heartbeat and dispatcher threads around protocol/'s state
// machines; what the reader thread does with the board's frames is in link_receive.cc.
#include "palpa/host/link.h"

#include <algorithm>
#include <chrono>
#include <random>

#include "palpa/protocol/faults.h"

namespace palpa::host {

std::string FaultName(uint8_t fault) {
  // A newer board may latch a fault this host has no name for: shown, never dropped.
  return fault < static_cast<uint8_t>(pp::Fault::kCount) ? pp::kFaultNames[fault]
                                                         : "fault_" + std::to_string(fault);
}

std::string FaultNames(uint32_t bitmap) {
  std::string text;
  for (uint8_t f = 0; f < 32; ++f) {
    if ((bitmap & (1u << f)) != 0) text += (text.empty() ? "" : ", ") + FaultName(f);
  }
  return text.empty() ? "none" : text;
}

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

namespace {

uint32_t RandomNonce() {
  static std::mt19937 rng(std::random_device{}());
  return static_cast<uint32_t>(rng()) | 1u;
}

}  // namespace

Link::Link(std::unique_ptr<Transport> transport, LinkOptions options)
    : transport_(std::move(transport)),
      description_(transport_->Describe()),
      options_(std::move(options)) {}

Result<std::unique_ptr<Link>> Link::Open(std::unique_ptr<Transport> transport,
                                         LinkOptions options) {
  std::unique_ptr<Link> link(new Link(std::move(transport), options));
  link->reader_ = std::thread(&Link::ReaderLoop, link.get());
  link->dispatcher_ = std::thread(&Link::DispatchLoop, link.get());
  // Heartbeats start with the session: the board counts only those naming it, and until its
  // reply arrives the Hello, resent with the same nonce, is what keeps the board's timer.
  link->heartbeat_ = std::thread(&Link::HeartbeatLoop, link.get());
  {
    std::unique_lock<std::mutex> lock(link->mutex_);
    const auto deadline =
        std::chrono::steady_clock::now() +
        std::chrono::milliseconds(options.hello_timeout_ms * options.hello_attempts);
    // Busy for longer than a silent host's session lasts (the board's timeout, in board time,
    // which runs at least as fast as ours), plus two Hello periods: the other host is alive.
    auto busy_for_good = [&] {
      if (link->busy_since_s_ < 0) return false;
      return SteadySeconds() - link->busy_since_s_ >
             link->busy_timeout_us_ / 1e6 + 2 * options.hello_timeout_ms / 1000.0;
    };
    while (!link->session_.open() && !link->stop_ && !busy_for_good() &&
           std::chrono::steady_clock::now() < deadline) {
      link->changed_.wait_for(lock, std::chrono::milliseconds(options.hello_timeout_ms));
    }
    if (!link->session_.open()) {
      const bool busy = link->busy_since_s_ >= 0;
      return {busy ? Status::kBusy : Status::kTimeout,
              busy ? "busy: another host holds the board (" + link->description_ +
                         "); it is free once that host closes its session, or goes silent "
                         "for the board's host-silence timeout"
                   : link->description_ + ": no answer to Hello (" +
                         std::to_string(options.hello_attempts) +
                         " tries); is it a palpa board, and is it powered?"};
    }
  }
  return link;
}

Link::~Link() {
  Close();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  queue_changed_.notify_all();
  if (reader_.joinable()) reader_.join();
  if (heartbeat_.joinable()) heartbeat_.join();
  if (dispatcher_.joinable()) dispatcher_.join();
}

pp::HelloReply Link::board() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_.board();
}

bool Link::catalog_matches() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_.catalog_matches();
}

bool Link::session_open() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_.open();
}

bool Link::ended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !session_.open() && !hello_wanted_ && !reopening_;
}

std::string Link::session_end() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return session_.open() ? std::string() : session_end_;
}

std::string Link::Versions() const {
  std::lock_guard<std::mutex> lock(mutex_);
  char text[200];
  session_.DescribeVersions(text, sizeof(text));
  return text;
}

void Link::WriteFrame(const uint8_t* frame, size_t size) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  if (transport_) transport_->Write(frame, size);  // none while a lost one is being reopened
}

template <class M>
void Link::SendUnsequenced(const M& m) {
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, 0, 0, frame, sizeof(frame));
  if (n.ok()) WriteFrame(frame, n.value);
}

void Link::SendHello() {  // mutex_ held
  if (!hello_wanted_) return;
  const double now = SteadySeconds();
  if (hello_sent_s_ >= 0 && now - hello_sent_s_ < options_.hello_timeout_ms / 1000.0) return;
  if (hello_sent_s_ < 0 || hello_nonce_ == 0) {
    hello_nonce_ = RandomNonce();
    session_.BeginHello(hello_nonce_);
  }
  const uint8_t initial_seq = static_cast<uint8_t>(hello_nonce_ >> 8);
  sender_.Reset(initial_seq);
  hello_sent_s_ = now;
  SendUnsequenced(pp::Hello{hello_nonce_, initial_seq});
}

CommandResult Link::CommandPacket(uint8_t type, const uint8_t* body, size_t size, int timeout_ms) {
  return Await(SubmitPacket(type, body, size, timeout_ms), timeout_ms);
}

uint32_t Link::SubmitPacket(uint8_t type, const uint8_t* body, size_t size, int timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::milliseconds(timeout_ms < 0 ? options_.command_timeout_ms : timeout_ms);
  const uint32_t cookie = next_cookie_++;
  auto fail = [&](CommandResult r) {  // answered at once: Await returns it
    host_timeout_.OnRefused(cookie);  // never sent: changed nothing
    pending_[cookie] = Pending{true, std::move(r)};
    return cookie;
  };
  // Waits for a session being opened; none is when this host closed it or lost the board.
  if (!changed_.wait_until(lock, deadline,
                           [&] { return session_.open() || stop_ || !hello_wanted_; }) ||
      !session_.open()) {
    return fail(CommandResult{
        Status::kNoSession,
        0,
        0,
        {},
        "no session with the board" + (session_end_.empty() ? "" : " (" + session_end_ + ")")});
  }
  const Status admitted = session_.Admit(type);
  if (admitted != Status::kOk) {
    char text[200];
    session_.DescribeVersions(text, sizeof(text));
    return fail(CommandResult{admitted, 0, 0, {}, std::string("refused: ") + text});
  }
  pending_[cookie] = Pending{};
  // Heartbeats fit a new timeout before it applies, whether it comes alone or in a staged blob.
  if (const auto carried = carried_.Carried(type, body, size)) {
    host_timeout_.OnSent(cookie, *carried);
    changed_.notify_all();
  }
  for (;;) {
    const auto seq = sender_.SubmitEncoded(type, body, size, cookie);
    if (seq.ok()) break;
    if (seq.status != Status::kWindowFull)
      return fail(CommandResult{seq.status, 0, 0, {}, "cannot queue the command"});
    // Until answers make room (by count and by bytes in flight: the board's receive buffer).
    if (!changed_.wait_until(lock, deadline, [&] { return sender_.HasRoomFor(size) || stop_; })) {
      return fail(
          CommandResult{Status::kWindowFull, 0, 0, {}, "the board does not take more commands"});
    }
  }
  sender_.Transmit(Micros(SteadySeconds()),
                   [this](const uint8_t* f, size_t n) { WriteFrame(f, n); });
  return cookie;
}

uint32_t Link::FailedTicket(CommandResult result) {
  std::lock_guard<std::mutex> lock(mutex_);
  const uint32_t cookie = next_cookie_++;
  pending_[cookie] = Pending{true, std::move(result)};
  return cookie;
}

CommandResult Link::Await(uint32_t ticket, int timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::milliseconds(timeout_ms < 0 ? options_.command_timeout_ms : timeout_ms);
  changed_.wait_until(lock, deadline, [&] { return pending_[ticket].done || stop_; });
  CommandResult result =
      pending_[ticket].done
          ? pending_[ticket].result
          : CommandResult{Status::kTimeout,
                          0,
                          0,
                          {},
                          "no answer from the board in time (the command may still be applied)"};
  if (!pending_[ticket].done) host_timeout_.OnUnknown(ticket);
  pending_.erase(ticket);
  return result;
}

void Link::DispatchLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    queue_changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const TelemetryFrame frame = queue_.front();
    queue_.pop_front();
    // One subscriber at a time, looked up afresh: one that unsubscribed meanwhile is not called.
    for (auto it = subscribers_.begin(); it != subscribers_.end() && !stop_;) {
      const int id = it->first;
      const auto callback = it->second;
      running_subscriber_ = id;
      lock.unlock();
      (*callback)(frame);  // outside the lock: may take its time
      lock.lock();
      running_subscriber_ = 0;
      callback_returned_.notify_all();
      it = subscribers_.upper_bound(id);
    }
  }
}

void Link::HeartbeatLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    if (session_.open() && !closed_) {
      ++counters_.heartbeats;
      const pp::Heartbeat hb{session_.session_tag(), ++heartbeat_generation_};
      lock.unlock();
      SendUnsequenced(hb);
      lock.lock();
    }
    // A quarter of the board's timeout, in host time (before the first reply, of the default).
    // A new session or a shorter timeout in flight shortens the period: wake up for it.
    const uint64_t changes = host_timeout_.changes();
    changed_.wait_for(lock, std::chrono::duration<double>(host_timeout_.HeartbeatPeriodSeconds()),
                      [&] { return stop_ || host_timeout_.changes() != changes; });
  }
}

void Link::SetHostTimeout(uint32_t host_timeout_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  host_timeout_.Set(host_timeout_us);
  changed_.notify_all();
}

template <class M>
uint32_t Link::StreamLatest(Stream& stream, M m) {
  std::unique_lock<std::mutex> lock(mutex_);
  // A value asked for while the link opens a new session (the board reset, or ended a session
  // this host let go silent) goes into that session: a stream is never replayed into a new
  // session by itself, but this one the application asks for now.
  changed_.wait_for(lock, std::chrono::milliseconds(options_.command_timeout_ms),
                    [&] { return session_.open() || stop_ || !hello_wanted_; });
  m.session = session_.session_tag();
  m.generation = ++stream.generation;
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, 0, 0, frame, sizeof(frame));
  if (!n.ok() || !session_.open()) {  // nothing goes out without a session to carry it
    stream.refused = n.ok() ? Status::kNoSession : n.status;
    stream.refused_detail = 0;
    stream.refused_generation = m.generation;
    return m.generation;
  }
  stream.frame.assign(frame, frame + n.value);
  stream.active = true;
  stream.sent_s = SteadySeconds();
  WriteFrame(frame, n.value);
  return m.generation;
}

uint32_t Link::StreamSetpoints(pp::SetLineSetpoints m) { return StreamLatest(setpoints_, m); }

uint32_t Link::StreamTargets(pp::SetFingerTargets m) { return StreamLatest(targets_, m); }

uint32_t Link::targets_generation() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return targets_.generation;
}

Status Link::WaitApplied(bool setpoints, uint32_t generation, int timeout_ms, uint32_t* detail) {
  std::unique_lock<std::mutex> lock(mutex_);
  Stream& s = setpoints ? setpoints_ : targets_;
  Status result = Status::kTimeout;
  changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] {
    if (s.refused_generation == generation) {
      result = s.refused;
      if (detail != nullptr) *detail = s.refused_detail;
      return true;
    }
    if (s.applied == generation || pp::GenerationNewer(s.applied, generation)) {
      result = Status::kOk;
      return true;
    }
    if (stop_ || !session_.open()) {
      result = Status::kNoSession;
      return true;
    }
    return false;
  });
  return result;
}

Status Link::WaitSetpointsApplied(uint32_t generation, int timeout_ms, uint32_t* detail) {
  return WaitApplied(true, generation, timeout_ms, detail);
}
Status Link::WaitTargetsApplied(uint32_t generation, int timeout_ms, uint32_t* detail) {
  return WaitApplied(false, generation, timeout_ms, detail);
}

Status Link::EStop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    estop_acked_ = false;
  }
  for (int attempt = 0; attempt < 25; ++attempt) {
    SendUnsequenced(pp::EStop{});
    std::unique_lock<std::mutex> lock(mutex_);
    if (changed_.wait_for(lock, std::chrono::milliseconds(20),
                          [&] { return estop_acked_ || stop_; }) &&
        estop_acked_) {
      return Status::kOk;
    }
  }
  return Status::kTimeout;
}

template <class M>
bool Link::RepeatUntilAnswered(std::unique_lock<std::mutex>& lock, const M& m, bool& answered) {
  answered = false;
  // A frame sent now waits behind what is in flight: on a 20 kB/s line during a flash, the
  // board's 4 KiB buffer, 200 ms. So it is resent once per retransmission timeout of the
  // reliable commands (their measured round trip), and waited for while the board is heard
  // (it is working through what went before); given up on after close_attempts resends of
  // silence, or close_wait_max_ms in all. A fixed 10 x 20 ms gave up on a board about to answer.
  const auto resend = std::chrono::milliseconds(
      std::max(options_.close_resend_ms, static_cast<int>((sender_.base_rto_us() + 999) / 1000)));
  const double silence_s = options_.close_attempts * std::chrono::duration<double>(resend).count();
  const double start = SteadySeconds();
  while (!stop_) {
    lock.unlock();
    SendUnsequenced(m);
    lock.lock();
    if (changed_.wait_for(lock, resend, [&] { return answered || stop_; }) && answered) return true;
    const double now = SteadySeconds();
    if (now - std::max(start, last_board_frame_s_) >= silence_s ||
        now - start >= options_.close_wait_max_ms / 1000.0) {
      break;
    }
  }
  return answered;
}

Status Link::Close() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (closed_) return Status::kOk;
  closed_ = true;  // heartbeats stop; no Hello, no reconnection from now on
  hello_wanted_ = false;
  setpoints_.active = targets_.active = false;
  changed_.notify_all();
  if (!session_.open()) return Status::kOk;
  if (!session_.catalog_matches()) {  // its Close may mean something else: silence ends it
    EndSession("closed by this host (without Close: the board runs other firmware)", false);
    return Status::kCatalogMismatch;
  }
  const bool heard = RepeatUntilAnswered(lock, pp::Close{session_.session_tag()}, close_answered_);
  EndSession(heard ? "closed by this host"
                   : "closed by this host; the board did not answer the Close, its host-silence "
                     "timeout ends the session",
             false);
  return heard ? Status::kOk : Status::kTimeout;
}

Status Link::Release() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!session_.open() || closed_) return Status::kNoSession;
  setpoints_.active = targets_.active = false;  // a resend must not actuate again
  release_status_ = Status::kTimeout;
  RepeatUntilAnswered(lock, pp::Release{session_.session_tag()}, release_answered_);
  return release_status_;
}

int Link::Subscribe(std::function<void(const TelemetryFrame&)> callback) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int id = next_subscriber_++;
  subscribers_[id] =
      std::make_shared<std::function<void(const TelemetryFrame&)>>(std::move(callback));
  return id;
}

void Link::Unsubscribe(int id) {
  std::unique_lock<std::mutex> lock(mutex_);
  subscribers_.erase(id);
  if (std::this_thread::get_id() == dispatcher_.get_id()) return;  // from its own callback
  callback_returned_.wait(lock, [&] { return running_subscriber_ != id; });
}

LinkCounters Link::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

double Link::BoardToHostSeconds(uint64_t board_us) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const double scale = session_.board().time_scale > 0 ? session_.board().time_scale : 1.0;
  return min_offset_s_ + static_cast<double>(board_us) / 1e6 / scale;
}

std::vector<std::string> Link::TakeEvents() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  out.swap(events_);
  return out;
}

}  // namespace palpa::host
