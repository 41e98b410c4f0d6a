// Endpoint transfers: buffers used in rotation, so queue order is delivery order.
#include "ffs_endpoints.h"

#include <cstring>

namespace palpa::gadget {

OutEndpoint::OutEndpoint(uint32_t id, size_t slots, size_t size) : id_(id), slots_(slots) {
  for (Slot& s : slots_) s.buffer.resize(size);
}

void OutEndpoint::Start(AioContext& aio, int fd) {
  // A buffer still queued (a read the kernel has not finished after a disable) is skipped over
  // only by stopping here: reads are delivered in rotation order.
  while (!slots_[next_queue_].queued && !slots_[next_queue_].done) {
    Slot& s = slots_[next_queue_];
    if (!aio.Submit(fd, false, s.buffer.data(), s.buffer.size(),
                    EndpointTag(id_, static_cast<uint32_t>(next_queue_)))) {
      return;  // not configured by the host (yet): Start again on enable
    }
    s.queued = true;
    next_queue_ = (next_queue_ + 1) % slots_.size();
  }
}

void OutEndpoint::Complete(uint32_t slot, int64_t result, AioContext& aio, int fd, bool requeue,
                           std::vector<uint8_t>& out) {
  if (slot >= slots_.size()) return;
  slots_[slot].queued = false;
  slots_[slot].done = true;
  slots_[slot].result = result;
  while (slots_[next_deliver_].done) {
    Slot& s = slots_[next_deliver_];
    if (s.result > 0) out.insert(out.end(), s.buffer.begin(), s.buffer.begin() + s.result);
    s.done = false;
    next_deliver_ = (next_deliver_ + 1) % slots_.size();
  }
  if (requeue) Start(aio, fd);
}

InEndpoint::InEndpoint(uint32_t id, size_t slots, size_t size)
    : id_(id), size_(size), buffers_(slots, std::vector<uint8_t>(size)), busy_(slots, false) {}

bool InEndpoint::CanSend() const { return !busy_[next_]; }

bool InEndpoint::Send(AioContext& aio, int fd, const uint8_t* data, size_t size) {
  if (busy_[next_] || size > size_) return false;
  std::memcpy(buffers_[next_].data(), data, size);
  if (!aio.Submit(fd, true, buffers_[next_].data(), size,
                  EndpointTag(id_, static_cast<uint32_t>(next_)))) {
    return false;
  }
  busy_[next_] = true;
  next_ = (next_ + 1) % buffers_.size();
  return true;
}

size_t InEndpoint::Complete(uint32_t slot, int64_t result) {
  if (slot >= busy_.size()) return 0;
  busy_[slot] = false;
  return result > 0 ? static_cast<size_t>(result) : 0;
}

size_t InEndpoint::in_flight() const {
  size_t n = 0;
  for (bool b : busy_) n += b ? 1 : 0;
  return n;
}

}  // namespace palpa::gadget
