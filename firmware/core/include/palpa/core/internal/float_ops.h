// Float helpers the loop-rate code shares, written for what the Cortex-M4F FPU can do.
#pragma once

#include <cstdint>
#include <limits>

namespace palpa::core {

/// One VABS on the FPU (a compare and a select otherwise); callers only compare the result, so
/// the sign of zero does not matter.
inline float Abs(float v) { return __builtin_fabsf(v); }

/// `v` held to [lo, hi] (the FPU has no min/max: two compares).
inline float Clamp(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

/// TruncateSaturating's portable form: clamps first, since C++ leaves an out-of-range conversion
/// undefined.
inline int32_t TruncateSaturatingPortable(float v) {
  if (!(v == v)) return 0;
  if (v >= 2147483648.0f) return std::numeric_limits<int32_t>::max();
  if (v <= -2147483648.0f) return std::numeric_limits<int32_t>::min();
  return static_cast<int32_t>(v);
}

/// `v` truncated toward zero to an int32, saturated at the int32 range (NaN gives 0): one VCVT
/// on the Cortex-M4F, whose conversion saturates by itself (the mps2 play check compares it
/// with the portable form on the target).
inline int32_t TruncateSaturating(float v) {
#if defined(__arm__) && defined(__ARM_FP)
  asm("vcvt.s32.f32 %0, %0" : "+t"(v));
  return __builtin_bit_cast(int32_t, v);
#else
  return TruncateSaturatingPortable(v);
#endif
}

/// A bound no pressure reaches: "no limit" without a second compare.
inline constexpr float kUnbounded = std::numeric_limits<float>::max();

}  // namespace palpa::core
