// Piecewise-linear interpolation and monotonicity checks.
#include "palpa/core/curve.h"

namespace palpa::core {

float Interpolate(const float* x, const float* y, uint8_t count, float at) {
  if (count == 0) return at;
  if (count == 1) return y[0];
  const bool rising = x[count - 1] > x[0];
  auto before = [rising](float a, float b) { return rising ? a <= b : a >= b; };
  if (before(at, x[0])) return y[0];
  if (before(x[count - 1], at)) return y[count - 1];
  // The first point past `at` (capped at the last), by bisection: the worst case is what a tick
  // pays, and a 24-point curve would otherwise take 23 comparisons.
  uint8_t i = 1;
  uint8_t last = static_cast<uint8_t>(count - 1);
  while (i < last) {
    const uint8_t mid = static_cast<uint8_t>((i + last) / 2);
    if (before(x[mid], at)) {
      i = static_cast<uint8_t>(mid + 1);
    } else {
      last = mid;
    }
  }
  const float span = x[i] - x[i - 1];
  const float t = span != 0.0f ? (at - x[i - 1]) / span : 0.0f;
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

int Direction(const int32_t* values, uint8_t count, bool strict) {
  int direction = 0;
  for (uint8_t i = 1; i < count; ++i) {
    const int32_t a = values[i - 1];
    const int32_t b = values[i];
    if (a == b) {
      if (strict) return 2;
      continue;
    }
    const int step = b > a ? 1 : -1;
    if (direction != 0 && step != direction) return 2;
    direction = step;
  }
  return direction;
}

}  // namespace palpa::core
