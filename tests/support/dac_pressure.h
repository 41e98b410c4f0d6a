// What a DAC code commands on a line, from the line's configuration alone: the tests' own
// inverse of the firmware's scaling, to check the codes the board writes.
#pragma once

#include <cmath>
#include <cstdint>

#include "palpa/protocol/messages_config.h"

namespace palpa::testing {

/// Pressure a DAC code commands on a line (0..100 % of the signal over the command range).
inline float PressureOfCounts(const protocol::ConfigureLine& c, uint32_t counts) {
  const float max = static_cast<float>((1u << c.dac_bits) - 1u);
  const float low = c.dac_signal == protocol::SignalRange::kMilliamp4To20 ? 0.2f * max : 0.0f;
  const float fraction = (static_cast<float>(counts) - low) / (max - low);
  return static_cast<float>(c.command_min_pa) +
         fraction * static_cast<float>(c.command_max_pa - c.command_min_pa);
}

/// One DAC step in pascal (a vacuum line's command range runs downwards).
inline float PressurePerCount(const protocol::ConfigureLine& c) {
  return std::fabs(static_cast<float>(c.command_max_pa - c.command_min_pa)) /
         static_cast<float>((1u << c.dac_bits) - 1u);
}

}  // namespace palpa::testing
