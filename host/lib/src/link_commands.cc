// The link's reliable commands: queued in the sender's window in the order of the calls, each
// awaited by its ticket until answered, refused, or out of time.
#include <chrono>

#include "palpa/host/link.h"

namespace palpa::host {

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

}  // namespace palpa::host
