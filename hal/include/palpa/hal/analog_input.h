// Analogue inputs (ADC channels) that read the pressure sensors.
#pragma once

#include <cstdint>

#include "palpa/protocol/status.h"

namespace palpa::hal {

using protocol::Result;

/// An ADC with several channels, read once per tick. Counts only: the transfer function from
/// counts to pressure is part of each line's configuration.
class AnalogInput {
 public:
  /// Returns counts, or kIoError when the conversion failed.
  Result<uint32_t> Read(uint8_t channel) { return DoRead(channel); }
  uint8_t bits() const { return DoBits(); }

 protected:
  ~AnalogInput() = default;

 private:
  virtual Result<uint32_t> DoRead(uint8_t channel) = 0;
  virtual uint8_t DoBits() const = 0;
};

}  // namespace palpa::hal
