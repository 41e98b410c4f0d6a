// Seeded byte-level damage: drops, bit flips, duplicates, swaps and delay.
#include "palpa/host/fault_transport.h"

#include <chrono>
#include <cstring>
#include <thread>

namespace palpa::host {
namespace {

int64_t NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

std::vector<uint8_t> FaultTransport::Damage(const uint8_t* data, size_t size) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<uint8_t> out;
  out.reserve(size + 8);
  for (size_t i = 0; i < size; ++i) {
    if (u(rng_) < spec_.drop) continue;
    uint8_t b = data[i];
    if (u(rng_) < spec_.bit_flip) b ^= static_cast<uint8_t>(1u << (rng_() % 8));
    out.push_back(b);
    if (u(rng_) < spec_.duplicate) out.push_back(b);
    if (out.size() >= 2 && u(rng_) < spec_.reorder)
      std::swap(out[out.size() - 1], out[out.size() - 2]);
  }
  return out;
}

protocol::Result<size_t> FaultTransport::Read(uint8_t* out, size_t capacity, int timeout_ms) {
  if (spec_.delay_ms == 0) {
    std::vector<uint8_t> raw(capacity);
    const auto n = inner_->Read(raw.data(), raw.size(), timeout_ms);
    if (!n.ok()) return n.status;
    const std::vector<uint8_t> damaged = Damage(raw.data(), n.value);
    const size_t count = damaged.size() < capacity ? damaged.size() : capacity;
    std::memcpy(out, damaged.data(), count);
    return count;
  }
  std::vector<uint8_t> raw(capacity);
  const auto n = inner_->Read(raw.data(), raw.size(), delayed_in_.empty() ? timeout_ms : 1);
  if (!n.ok()) return n.status;
  if (n.value > 0)
    delayed_in_.push_back(Timed{NowMs() + spec_.delay_ms, Damage(raw.data(), n.value)});
  size_t count = 0;
  while (!delayed_in_.empty() && delayed_in_.front().due_ms <= NowMs() && count < capacity) {
    Timed& t = delayed_in_.front();
    const size_t take = t.bytes.size() < capacity - count ? t.bytes.size() : capacity - count;
    std::memcpy(out + count, t.bytes.data(), take);
    count += take;
    t.bytes.erase(t.bytes.begin(), t.bytes.begin() + static_cast<long>(take));
    if (t.bytes.empty()) delayed_in_.pop_front();
  }
  return count;
}

Status FaultTransport::Write(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> damaged = Damage(data, size);
  if (spec_.delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(spec_.delay_ms));
  return damaged.empty() ? Status::kOk : inner_->Write(damaged.data(), damaged.size());
}

}  // namespace palpa::host
