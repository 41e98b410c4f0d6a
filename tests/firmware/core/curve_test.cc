// Piecewise-linear curves: interpolation in both directions, at and between the points and
// beyond the ends, against a straightforward reference.
#include <algorithm>
#include <random>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "palpa/core/curve.h"

namespace pc = palpa::core;

namespace {

/// The segment containing `at` found by walking the points; clamped to the ends outside.
double Reference(const std::vector<float>& x, const std::vector<float>& y, float at) {
  const bool rising = x.back() > x.front();
  auto before = [rising](float a, float b) { return rising ? a <= b : a >= b; };
  if (before(at, x.front())) return y.front();
  if (before(x.back(), at)) return y.back();
  size_t i = 1;
  while (i + 1 < x.size() && before(x[i], at)) ++i;
  return y[i - 1] + (static_cast<double>(at) - x[i - 1]) / (x[i] - x[i - 1]) * (y[i] - y[i - 1]);
}

}  // namespace

TEST_GROUP(Curve){};

TEST(Curve, InterpolatesEveryCurveLengthBothWaysAsTheReferenceDoes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> step(1, 500);
  for (int count = 2; count <= 24; ++count) {
    for (int direction : {1, -1}) {
      std::vector<float> x, y;
      float xv = 1000, yv = 0;
      for (int i = 0; i < count; ++i) {
        x.push_back(xv += direction * step(rng));
        y.push_back(yv += step(rng));
      }
      std::vector<float> probes(x);  // on every point, between them and beyond both ends
      for (int i = 0; i + 1 < count; ++i) probes.push_back(0.5f * (x[i] + x[i + 1]));
      probes.push_back(x.front() - direction * 100.0f);
      probes.push_back(x.back() + direction * 100.0f);
      for (float at : probes) {
        const double expected = Reference(x, y, at);
        DOUBLES_EQUAL(expected,
                      pc::Interpolate(x.data(), y.data(), static_cast<uint8_t>(count), at),
                      1e-3 + 1e-6 * std::abs(expected));
      }
    }
  }
}

TEST(Curve, DegenerateCurvesAreTheIdentityOrAConstant) {
  const float x[] = {5};
  const float y[] = {7};
  DOUBLES_EQUAL(3, pc::Interpolate(x, y, 0, 3), 0);
  DOUBLES_EQUAL(7, pc::Interpolate(x, y, 1, 3), 0);
}
