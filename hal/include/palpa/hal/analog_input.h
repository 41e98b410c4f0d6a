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
  /// In ReadAll's counts: this channel's conversion failed (no ADC delivers all ones).
  static constexpr uint32_t kConversionFailed = 0xFFFFFFFFu;

  /// Returns counts, or kIoError when the conversion failed.
  Result<uint32_t> Read(uint8_t channel) { return DoRead(channel); }
  /// Channels 0..count-1 of one scan, as the tick takes them: counts[i], or kConversionFailed.
  void ReadAll(uint32_t* counts, uint8_t count) { DoReadAll(counts, count); }
  uint8_t bits() const { return DoBits(); }

 protected:
  ~AnalogInput() = default;

 private:
  virtual Result<uint32_t> DoRead(uint8_t channel) = 0;
  /// A scanning ADC hands over its whole buffer; the default reads channel by channel.
  virtual void DoReadAll(uint32_t* counts, uint8_t count) {
    for (uint8_t i = 0; i < count; ++i) {
      const Result<uint32_t> r = DoRead(i);
      counts[i] = r.ok() ? r.value : kConversionFailed;
    }
  }
  virtual uint8_t DoBits() const = 0;
};

}  // namespace palpa::hal
