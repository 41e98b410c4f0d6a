// Two 16-bit lanes in one word: the play operators' integer arithmetic, ARMv7E-M DSP or portable.
//
// The PI step clamps two play operators per instruction pair with the DSP extension's GE flags
// (SSUB16/SADD16 then SEL), since the Cortex-M4's FPU has neither min nor max. The portable
// versions compute the same bits, so the host, the simulator and the board agree exactly.
#pragma once

#include <cstdint>

#if defined(__ARM_FEATURE_SIMD32) && __ARM_FEATURE_SIMD32
#include <arm_acle.h>
#define PALPA_PLAY_LANES_DSP 1
#endif

namespace palpa::core::lanes {

inline int32_t Low(uint32_t v) { return static_cast<int16_t>(v & 0xFFFFu); }
inline int32_t High(uint32_t v) { return static_cast<int16_t>(v >> 16); }
inline uint32_t Pack(int32_t low, int32_t high) {
  return (static_cast<uint32_t>(low) & 0xFFFFu) | (static_cast<uint32_t>(high) << 16);
}
/// Operator i's lane of a pair word (even i low, odd i high), as PlayPair lays them out.
inline int32_t Lane(uint32_t v, uint8_t i) { return i % 2 == 0 ? Low(v) : High(v); }

/// v saturated to the int16 range (SSAT #16).
inline int32_t Saturate(int32_t v) {
#ifdef PALPA_PLAY_LANES_DSP
  return __ssat(v, 16);
#else
  return v > 32767 ? 32767 : (v < -32768 ? -32768 : v);
#endif
}

/// Saturate31's portable form.
inline int32_t Saturate31Portable(int32_t v) {
  return v > 1073741823 ? 1073741823 : (v < -1073741824 ? -1073741824 : v);
}

/// v saturated to [−2³⁰, 2³⁰ − 1] (SSAT #31).
inline int32_t Saturate31(int32_t v) {
#ifdef PALPA_PLAY_LANES_DSP
  return __ssat(v, 31);
#else
  return Saturate31Portable(v);
#endif
}

/// Both lanes of a + b, each saturated to int16 (QADD16).
inline uint32_t SaturatingAdd(uint32_t a, uint32_t b) {
#ifdef PALPA_PLAY_LANES_DSP
  return static_cast<uint32_t>(__qadd16(static_cast<int16x2_t>(a), static_cast<int16x2_t>(b)));
#else
  return Pack(Saturate(Low(a) + Low(b)), Saturate(High(a) + High(b)));
#endif
}

/// Each lane of v held to at most `bound` (SSUB16 sets GE where v ≥ bound; SEL takes the bound).
inline uint32_t Min(uint32_t v, uint32_t bound) {
#ifdef PALPA_PLAY_LANES_DSP
  (void)__ssub16(static_cast<int16x2_t>(v), static_cast<int16x2_t>(bound));
  return __sel(bound, v);
#else
  auto min = [](int32_t x, int32_t hi) { return x >= hi ? hi : x; };
  return Pack(min(Low(v), Low(bound)), min(High(v), High(bound)));
#endif
}

/// Each lane of v held to at least −bound; `negative` holds −bound. bound ≥ 0. (SADD16 sets GE
/// where v ≥ −bound; SEL keeps v there.)
inline uint32_t Max(uint32_t v, uint32_t bound, uint32_t negative) {
#ifdef PALPA_PLAY_LANES_DSP
  (void)__sadd16(static_cast<int16x2_t>(v), static_cast<int16x2_t>(bound));
  return __sel(v, negative);
#else
  (void)bound;
  auto max = [](int32_t x, int32_t lo) { return x >= lo ? x : lo; };
  return Pack(max(Low(v), Low(negative)), max(High(v), High(negative)));
#endif
}

/// Each lane of v clamped to [−bound, bound]; `negative` holds −bound. bound ≥ 0. (SSUB16 and
/// SEL, then SADD16 and SEL: the GE flags come from the exact 17-bit results.)
inline uint32_t Clamp(uint32_t v, uint32_t bound, uint32_t negative) {
  return Max(Min(v, bound), bound, negative);
}

/// acc + low(a)·low(b), wrapping like SMLABB (the scales keep the true sums in range).
inline int32_t MulAddLow(uint32_t a, uint32_t b, int32_t acc) {
#ifdef PALPA_PLAY_LANES_DSP
  return __smlabb(static_cast<int32_t>(a), static_cast<int32_t>(b), acc);
#else
  return static_cast<int32_t>(static_cast<uint32_t>(acc) + static_cast<uint32_t>(Low(a) * Low(b)));
#endif
}

/// acc + high(a)·high(b) (SMLATT).
inline int32_t MulAddHigh(uint32_t a, uint32_t b, int32_t acc) {
#ifdef PALPA_PLAY_LANES_DSP
  return __smlatt(static_cast<int32_t>(a), static_cast<int32_t>(b), acc);
#else
  return static_cast<int32_t>(static_cast<uint32_t>(acc) +
                              static_cast<uint32_t>(High(a) * High(b)));
#endif
}

/// acc + low(a)·low(b) + high(a)·high(b) (SMLAD).
inline int32_t DualMulAdd(uint32_t a, uint32_t b, int32_t acc) {
#ifdef PALPA_PLAY_LANES_DSP
  return __smlad(static_cast<int16x2_t>(a), static_cast<int16x2_t>(b), acc);
#else
  return MulAddHigh(a, b, MulAddLow(a, b, acc));
#endif
}

/// The upper halves of two words as one pair (PKHTB ..., ASR #16): each value divided by 2¹⁶,
/// rounded down. `high` goes to the high lane.
inline uint32_t UpperHalves(int32_t low, int32_t high) {
  return (static_cast<uint32_t>(high) & 0xFFFF0000u) | (static_cast<uint32_t>(low) >> 16);
}

}  // namespace palpa::core::lanes
