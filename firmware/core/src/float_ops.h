// Float helpers the loop-rate code shares, written for what the Cortex-M4F FPU can do.
#pragma once

#include <limits>

namespace palpa::core {

/// One VABS on the FPU (a compare and a select otherwise); callers only compare the result, so
/// the sign of zero does not matter.
inline float Abs(float v) { return __builtin_fabsf(v); }

/// `v` held to [lo, hi] (the FPU has no min/max: two compares).
inline float Clamp(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

/// A bound no pressure reaches: "no limit" without a second compare.
inline constexpr float kUnbounded = std::numeric_limits<float>::max();

}  // namespace palpa::core
