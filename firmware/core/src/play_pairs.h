// The play-operator pass of the PI step, two operators per word: portable and ARMv7E-M versions.
#pragma once

#include <cstdint>

#include "palpa/core/compensator.h"

extern "C" int32_t palpa_play_pairs_v7em(const palpa::core::PlayPair* end, uint32_t* memory_end,
                                         const palpa::core::PlayPair* begin, uint32_t shift,
                                         int32_t later);

namespace palpa::core {

/// Top pair first: each forward operator's memory (relative to the last applied drive) moves by
/// `shift` (the drive's change, in both lanes, saturated) and stops at its clamp on the side it
/// moves towards: min(c + shift, r) while the drive rises (shift ≥ 0), max(c + shift, −r) while
/// it falls, which is the clamp to ±r for every memory a history can leave. Each inverse state
/// (`later` + W_i c_i, `later` then gaining w_i c_i) is clamped to ±r' in its upper 16 bits and
/// weighted into the returned sum. `later` starts at W_n a − v in sum steps.
int32_t PlayPairsPortable(const PlayPair* pairs, uint32_t* memory, uint8_t pair_count,
                          uint32_t shift, int32_t later);

inline int32_t PlayPairs(const PlayPair* pairs, uint32_t* memory, uint8_t pair_count,
                         uint32_t shift, int32_t later) {
#ifdef PALPA_PLAY_PAIRS_V7EM
  if (pair_count == 0) return 0;
  return palpa_play_pairs_v7em(pairs + pair_count, memory + pair_count, pairs, shift, later);
#else
  return PlayPairsPortable(pairs, memory, pair_count, shift, later);
#endif
}

}  // namespace palpa::core
