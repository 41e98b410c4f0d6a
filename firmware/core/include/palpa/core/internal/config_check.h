// Internal to firmware/core: the live configuration's integrity check — a CRC over its memory,
// recomputed a slice per tick and compared with the CRC taken when it was applied.
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"

namespace palpa::core {

class ConfigCheck {
 public:
  /// A new live configuration: its CRC now, a pass due at `now_us`.
  void Restart(const BoardConfig& live, uint64_t now_us);
  /// One slice of the pass (a pass starts every check period and takes a few ticks). Returns
  /// whether the configuration was intact at the last completed pass.
  bool Step(const BoardConfig& live, uint64_t now_us);

 private:
  uint32_t memory_crc_ = 0;
  uint32_t pass_crc_ = 0;
  uint32_t offset_ = 0;
  uint64_t next_pass_us_ = 0;
  bool intact_ = true;
};

}  // namespace palpa::core
