// The stiffness surface on functions with known answers: it interpolates a smooth map, does not
// sag between the rows of a coarse grid, sees its own noise in cross-validation, and asks for
// the next press where it knows least.
#include <cmath>
#include <random>
#include <vector>

#include "palpa/calibration/stiffness_surface.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;

namespace {

double Smooth(double bias, double vacuum) {
  return 0.7 + 0.006 * -vacuum + 0.004 * bias * (-vacuum / 100) + 0.1 * std::sin(-vacuum / 30);
}

std::vector<cal::MapSample> On(const std::vector<cal::MapSample>& at, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, noise);
  std::vector<cal::MapSample> out;
  for (const cal::MapSample& c : at) {
    out.push_back({c.bias_kpa, c.vacuum_kpa, Smooth(c.bias_kpa, c.vacuum_kpa) * (1 + n(rng))});
  }
  return out;
}

double WorstRelativeError(const cal::StiffnessSurface& s) {
  double worst = 0;
  for (double b = 0; b <= 20; b += 2.5) {
    for (double v = 0; v <= 100; v += 2.5) {
      const double truth = Smooth(b, -v);
      worst = std::max(worst, std::fabs(s.Predict(b, -v).mean - truth) / truth);
    }
  }
  return worst;
}

}  // namespace

TEST_GROUP(StiffnessSurface){};

TEST(StiffnessSurface, InterpolatesASmoothMapFromALattice) {
  const cal::StiffnessSurface s(On(cal::Lattice({}, 3, 9), 0, 1), {});
  CHECK(s.ok());
  LONGS_EQUAL(27, s.conditions());
  CHECK(WorstRelativeError(s) < 0.01);
  CHECK(s.CrossValidatedError() < 0.02);
  // Where it pressed it is sure; between it is less sure, and the sd says so.
  CHECK(s.Predict(10, -50).sd < s.Predict(5, -56.25).sd);
}

TEST(StiffnessSurface, ACoarseGridDoesNotSagBetweenItsRows) {
  // A straight ramp sampled on the thesis's 3 × 3: mid-cell the surface stays within 5 % of the
  // ramp (without the spacing rule a short length scale lets it fall back toward the mean).
  std::vector<cal::MapSample> grid;
  for (double b : {0.0, 10.0, 20.0}) {
    for (double v : {0.0, -50.0, -100.0}) grid.push_back({b, v, 0.7 + 0.006 * -v + 0.01 * b});
  }
  const cal::StiffnessSurface s(grid, {});
  DOUBLES_EQUAL(0.7 + 0.006 * 25 + 0.05, s.Predict(5, -25).mean, 0.05 * 0.9);
  DOUBLES_EQUAL(0.7 + 0.006 * 75 + 0.15, s.Predict(15, -75).mean, 0.05 * 1.3);
}

TEST(StiffnessSurface, CrossValidationSeesThePressNoise) {
  const cal::StiffnessSurface clean(On(cal::Lattice({}, 3, 11), 0, 2), {});
  const cal::StiffnessSurface noisy(On(cal::Lattice({}, 3, 11), 0.03, 2), {});
  CHECK(clean.CrossValidatedError() < 0.01);
  CHECK(noisy.CrossValidatedError() > 0.02);
  CHECK(noisy.CrossValidatedError() < 0.06);
  CHECK(noisy.PressNoise() > 0.01);
}

TEST(StiffnessSurface, TheNextPressGoesWhereItKnowsLeast) {
  // Everything at full bias: the next press goes well away from that row.
  std::vector<cal::MapSample> at;
  for (double v = 0; v <= 100; v += 20) at.push_back({20, -v, 0});
  const cal::StiffnessSurface s(On(at, 0, 3), {});
  const cal::MapSample next = cal::NextCondition(s, cal::Lattice({}, 9, 21));
  CHECK(next.bias_kpa <= 12.5);
}

TEST(StiffnessSurface, RefusesWhatCannotMakeASurface) {
  CHECK_FALSE(cal::StiffnessSurface({}, {}).ok());
  CHECK_FALSE(cal::StiffnessSurface({{10, -50, 1.0}, {10, -50, 1.01}}, {}).ok());
  // Non-finite readings are left out, not propagated.
  const cal::StiffnessSurface s({{0, 0, 0.7}, {20, -100, 1.3}, {10, -50, NAN}}, {});
  CHECK(s.ok());
  CHECK(std::isfinite(s.Predict(10, -50).mean));
}
