// In-memory fakes of the small hal interfaces, for tests on the host.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/watchdog.h"

namespace palpa::hal::fake {

inline constexpr uint8_t kChannels = 8;

class FakeAnalogOutput final : public AnalogOutput {
 public:
  std::array<uint32_t, kChannels> counts{};
  std::array<AnalogOutputSpec, kChannels> specs{};
  uint32_t writes = 0;
  bool fail = false;

 private:
  Status DoWrite(uint8_t channel, uint32_t value) override {
    if (fail || channel >= kChannels) return Status::kIoError;
    counts[channel] = value;
    ++writes;
    return Status::kOk;
  }
  AnalogOutputSpec DoSpec(uint8_t channel) const override {
    return channel < kChannels ? specs[channel] : AnalogOutputSpec{};
  }
};

class FakeAnalogInput final : public AnalogInput {
 public:
  std::array<uint32_t, kChannels> counts{};
  uint8_t resolution = 14;
  bool fail = false;

 private:
  Result<uint32_t> DoRead(uint8_t channel) override {
    if (fail || channel >= kChannels) return protocol::Status::kIoError;
    return counts[channel];
  }
  uint8_t DoBits() const override { return resolution; }
};

/// An output whose writes fail (the level kept) while `fail` is set.
class FakeDigitalOutput final : public DigitalOutput {
 public:
  bool level = false;
  uint32_t changes = 0;
  bool fail = false;

 private:
  Status DoSet(bool value) override {
    if (fail) return Status::kIoError;
    changes += value != level;
    level = value;
    return Status::kOk;
  }
};

/// A port of one bit per output; writing output `fail_bit` fails (its bit kept) while it is set.
class FakeDigitalPort final : public DigitalPort {
 public:
  uint32_t bits = 0;
  uint32_t writes = 0;
  uint8_t fail_bit = kAllWritten;

 private:
  uint8_t DoWrite(uint32_t value) override {
    ++writes;
    if (fail_bit == kAllWritten) {
      bits = value;
      return kAllWritten;
    }
    const uint32_t kept = 1u << fail_bit;
    bits = (value & ~kept) | (bits & kept);
    return fail_bit;
  }
};

class FakeDigitalInput final : public DigitalInput {
 public:
  bool level = false;

 private:
  bool DoRead() override { return level; }
};

class FakeClock final : public Clock {
 public:
  uint64_t now_us = 0;
  void Advance(uint64_t us) { now_us += us; }

 private:
  uint64_t DoNowMicros() override { return now_us; }
};

class FakeWatchdog final : public Watchdog {
 public:
  uint32_t timeout_ms = 0;
  uint32_t kicks = 0;

 private:
  void DoStart(uint32_t ms) override { timeout_ms = ms; }
  void DoKick() override { ++kicks; }
};

/// Bytes in from the test, bytes out to the test; the transmit side has a bounded buffer so
/// back-pressure can be provoked.
class FakeByteLink final : public ByteLink {
 public:
  std::deque<uint8_t> rx;
  std::vector<uint8_t> tx;
  size_t tx_capacity = 1 << 20;

  void Inject(const uint8_t* data, size_t size) { rx.insert(rx.end(), data, data + size); }

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override {
    size_t n = 0;
    while (n < capacity && !rx.empty()) {
      out[n++] = rx.front();
      rx.pop_front();
    }
    return n;
  }
  size_t DoWrite(const uint8_t* data, size_t size) override {
    const size_t n = size < DoWriteSpace() ? size : DoWriteSpace();
    tx.insert(tx.end(), data, data + n);
    return n;
  }
  size_t DoWriteSpace() const override {
    return tx.size() < tx_capacity ? tx_capacity - tx.size() : 0;
  }
};

}  // namespace palpa::hal::fake
