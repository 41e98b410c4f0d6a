// A transport wrapper that damages the byte stream on purpose (seeded): for tests and benchmarks
// of the link's recovery.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <random>
#include <vector>

#include "palpa/host/transport.h"

namespace palpa::host {

struct FaultSpec {
  double drop = 0;       ///< probability a byte vanishes
  double bit_flip = 0;   ///< probability a byte has one bit flipped
  double duplicate = 0;  ///< probability a byte arrives twice
  double reorder = 0;    ///< probability two neighbouring bytes swap
  int delay_ms = 0;      ///< extra latency of every byte, both ways
};

class FaultTransport final : public Transport {
 public:
  FaultTransport(std::unique_ptr<Transport> inner, FaultSpec spec, uint32_t seed)
      : inner_(std::move(inner)), spec_(spec), rng_(seed) {}
  protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override;
  Status Write(const uint8_t* data, size_t size) override;
  std::string Describe() const override { return inner_->Describe() + " (with injected faults)"; }

 private:
  std::vector<uint8_t> Damage(const uint8_t* data, size_t size);
  std::unique_ptr<Transport> inner_;
  FaultSpec spec_;
  std::mutex mutex_;
  std::mt19937 rng_;
  struct Timed {
    int64_t due_ms;
    std::vector<uint8_t> bytes;
  };
  std::deque<Timed> delayed_in_;
};

}  // namespace palpa::host
