// A host Transport whose other end is the protocol tests' TestBoard, in-process.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>

#include "link_harness.h"
#include "palpa/host/transport.h"

namespace palpa::testing {

class BoardTransport final : public host::Transport {
 public:
  explicit BoardTransport(TestBoard& board) : board_(board) {}
  protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override;
  host::Status Write(const uint8_t* data, size_t size) override;
  std::string Describe() const override { return "test board"; }
  /// Reboots the board (a new boot nonce; the session is gone).
  void Reboot();

 private:
  using Result = protocol::Result<size_t>;
  TestBoard& board_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<uint8_t> to_host_;
};

}  // namespace palpa::testing
