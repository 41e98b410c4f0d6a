// Monotone piecewise-linear curves: regulator correction and finger static inverse.
#pragma once

#include <cstdint>

namespace palpa::core {

/// y(x) by linear interpolation over `count` points with x strictly monotone (either direction);
/// clamped to the end points outside the range (callers reject out-of-range inputs first).
float Interpolate(const float* x, const float* y, uint8_t count, float at);

/// Direction of a sequence: +1 rising, -1 falling, 0 constant (or fewer than two values),
/// 2 when it changes direction (or repeats a value, when `strict`).
int Direction(const int32_t* values, uint8_t count, bool strict);

}  // namespace palpa::core
