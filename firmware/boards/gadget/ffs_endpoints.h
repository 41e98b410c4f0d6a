// Transfers on FunctionFS endpoint files through native AIO: an OUT endpoint keeps reads queued
// and hands their data on in the order they were queued; an IN endpoint sends from a few buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "aio.h"

namespace palpa::gadget {

/// A completion's tag: which endpoint (high bits) and which of its buffers.
inline constexpr uint64_t EndpointTag(uint32_t endpoint, uint32_t slot) {
  return (static_cast<uint64_t>(endpoint) << 16) | slot;
}
inline constexpr uint32_t TagEndpoint(uint64_t tag) { return static_cast<uint32_t>(tag >> 16); }
inline constexpr uint32_t TagSlot(uint64_t tag) { return static_cast<uint32_t>(tag & 0xFFFF); }

class OutEndpoint {
 public:
  /// `slots` reads of `size` bytes each (a maximum packet: a host that sends no zero-length
  /// packet after a multiple of it would otherwise leave a larger read waiting).
  OutEndpoint(uint32_t id, size_t slots, size_t size);
  /// Queues reads on every idle buffer, in order.
  void Start(AioContext& aio, int fd);
  /// A finished read: appends what arrived, in queue order, to `out`; queues the buffers again
  /// while `requeue`.
  void Complete(uint32_t slot, int64_t result, AioContext& aio, int fd, bool requeue,
                std::vector<uint8_t>& out);

 private:
  struct Slot {
    std::vector<uint8_t> buffer;
    bool queued = false, done = false;
    int64_t result = 0;
  };
  uint32_t id_;
  std::vector<Slot> slots_;
  size_t next_queue_ = 0, next_deliver_ = 0;
};

class InEndpoint {
 public:
  InEndpoint(uint32_t id, size_t slots, size_t size);
  /// Bytes one transfer may carry.
  size_t capacity() const { return size_; }
  bool CanSend() const;
  /// Sends `size` ≤ capacity() bytes; false when no buffer is free or the kernel refused.
  bool Send(AioContext& aio, int fd, const uint8_t* data, size_t size);
  /// A finished write: its buffer is free again. Returns the bytes it moved (0 on an error).
  size_t Complete(uint32_t slot, int64_t result);
  size_t in_flight() const;

 private:
  uint32_t id_;
  size_t size_;
  std::vector<std::vector<uint8_t>> buffers_;
  std::vector<bool> busy_;
  size_t next_ = 0;
};

}  // namespace palpa::gadget
