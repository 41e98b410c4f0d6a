// Analogue outputs (DAC channels) that command the regulators.
#pragma once

#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/status.h"

namespace palpa::hal {

using protocol::SignalRange;
using protocol::Status;

/// Resolution and electrical range of one output channel.
struct AnalogOutputSpec {
  uint8_t bits = 12;
  SignalRange range = SignalRange::kVolt0To10;
  constexpr uint32_t max_counts() const { return (1u << bits) - 1u; }
};

/// A DAC with several channels. Writing a code may fail (bus error); the caller decides what a
/// failed write means for safety.
class AnalogOutput {
 public:
  /// In WriteAll's answer: every channel took its code.
  static constexpr uint8_t kAllWritten = 0xFF;

  Status Write(uint8_t channel, uint32_t counts) { return DoWrite(channel, counts); }
  /// Channels 0..count-1 to codes[i], as the tick writes them: every write is attempted; returns
  /// the first channel whose write failed, or kAllWritten.
  uint8_t WriteAll(const uint32_t* codes, uint8_t count) { return DoWriteAll(codes, count); }
  AnalogOutputSpec spec(uint8_t channel) const { return DoSpec(channel); }

 protected:
  ~AnalogOutput() = default;  // not deleted through this interface (no heap on the target)

 private:
  virtual Status DoWrite(uint8_t channel, uint32_t counts) = 0;
  /// A DAC that takes all its codes in one transfer overrides this; the default writes channel by
  /// channel.
  virtual uint8_t DoWriteAll(const uint32_t* codes, uint8_t count) {
    uint8_t failed = kAllWritten;
    for (uint8_t i = 0; i < count; ++i) {
      if (DoWrite(i, codes[i]) != Status::kOk && failed == kAllWritten) failed = i;
    }
    return failed;
  }
  virtual AnalogOutputSpec DoSpec(uint8_t channel) const = 0;
};

}  // namespace palpa::hal
