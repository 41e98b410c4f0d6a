// In-process transport to a TestBoard.
#include "board_transport.h"

#include <chrono>

namespace palpa::testing {

protocol::Result<size_t> BoardTransport::Read(uint8_t* out, size_t capacity, int timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return !to_host_.empty(); });
  size_t n = 0;
  while (n < capacity && !to_host_.empty()) {
    out[n++] = to_host_.front();
    to_host_.pop_front();
  }
  return n;
}

host::Status BoardTransport::Write(const uint8_t* data, size_t size) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::vector<uint8_t>> replies;
  board_.Receive(std::vector<uint8_t>(data, data + size), replies);
  for (const auto& r : replies) to_host_.insert(to_host_.end(), r.begin(), r.end());
  if (!replies.empty()) ready_.notify_all();
  return host::Status::kOk;
}

void BoardTransport::Reboot() {
  std::lock_guard<std::mutex> lock(mutex_);
  board_.Reboot();
}

}  // namespace palpa::testing
