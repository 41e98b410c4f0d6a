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
  Status Write(uint8_t channel, uint32_t counts) { return DoWrite(channel, counts); }
  AnalogOutputSpec spec(uint8_t channel) const { return DoSpec(channel); }

 protected:
  ~AnalogOutput() = default;  // not deleted through this interface (no heap on the target)

 private:
  virtual Status DoWrite(uint8_t channel, uint32_t counts) = 0;
  virtual AnalogOutputSpec DoSpec(uint8_t channel) const = 0;
};

}  // namespace palpa::hal
