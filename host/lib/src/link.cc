// The link's session: opened by Hello, kept by heartbeats, ended by Close, EStop and Release;
// commands, streams, telemetry and the reader thread have files of their own (link_*.cc).
#include "palpa/host/link.h"

#include <algorithm>
#include <chrono>
#include <random>

namespace palpa::host {

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

LinkCounters Link::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

std::vector<std::string> Link::TakeEvents() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  out.swap(events_);
  return out;
}

}  // namespace palpa::host
