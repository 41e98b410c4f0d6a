// Linux native AIO (io_submit) with an eventfd that polls readable on completions: FunctionFS
// endpoint files block until the host moves the data and cannot be polled, so a single-threaded
// gadget queues its transfers this way.
#pragma once

#include <linux/aio_abi.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace palpa::gadget {

class AioContext {
 public:
  AioContext() = default;
  ~AioContext();
  AioContext(const AioContext&) = delete;
  AioContext& operator=(const AioContext&) = delete;

  bool Open(unsigned max_in_flight, std::string* error);
  /// Queues one read or write of `size` bytes at `buffer` (which must stay valid until it
  /// completes); `tag` comes back with the completion. False when the kernel refuses it.
  bool Submit(int fd, bool write, void* buffer, size_t size, uint64_t tag);
  /// Calls `done(tag, result)` for every finished transfer (result: bytes moved or -errno).
  void Reap(const std::function<void(uint64_t tag, int64_t result)>& done);
  /// Readable while completions wait to be reaped.
  int poll_fd() const { return event_fd_; }

 private:
  aio_context_t context_ = 0;
  int event_fd_ = -1;
};

}  // namespace palpa::gadget
