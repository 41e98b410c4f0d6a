// The play-operator pass of the PI step in portable C++ (the DSP intrinsics where the core has
// them).
#include "play_pairs.h"

#include "play_lanes.h"

namespace palpa::core {

int32_t PlayPairsPortable(const PlayPair* pairs, uint32_t* memory, uint8_t pair_count,
                          uint32_t shift, int32_t later) {
  const bool rising = lanes::High(shift) >= 0;
  int32_t drive = 0;
  const PlayPair* pair = pairs + pair_count;
  memory += pair_count;
  while (pair != pairs) {
    --pair;
    --memory;
    const uint32_t moved = lanes::SaturatingAdd(*memory, shift);
    const uint32_t c = rising ? lanes::Min(moved, pair->threshold)
                              : lanes::Max(moved, pair->threshold, pair->negative_threshold);
    *memory = c;
    const int32_t high = lanes::MulAddHigh(c, pair->cumulative, later);
    const int32_t low = lanes::DualMulAdd(c, pair->mixed, later);
    later = lanes::DualMulAdd(c, pair->weight, later);
    const uint32_t states = lanes::Clamp(lanes::UpperHalves(low, high), pair->inverse_threshold,
                                         pair->negative_inverse_threshold);
    drive = lanes::DualMulAdd(states, pair->inverse_weight, drive);
  }
  return drive;
}

}  // namespace palpa::core
