// NNLS: equals ordinary least squares when that is feasible, and the constrained optimum (by
// exhaustive search over active sets) when it is not.
#include <algorithm>
#include <cmath>
#include <random>

#include "palpa/calibration/nnls.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;

namespace {

double Cost(const cal::Matrix& a, const std::vector<double>& b, const std::vector<double>& x) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    double f = -b[i];
    for (size_t j = 0; j < x.size(); ++j) f += a[i][j] * x[j];
    s += f * f;
  }
  return s;
}

}  // namespace

TEST_GROUP(Nnls){};

TEST(Nnls, RecoversAPositiveSolutionExactly) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(0, 1);
  cal::Matrix a(40, std::vector<double>(4));
  std::vector<double> b(40);
  const double truth[] = {2, 0.5, 3, 1e-3};
  for (size_t i = 0; i < 40; ++i) {
    for (size_t j = 0; j < 4; ++j) a[i][j] = d(rng) * (j == 3 ? 1e5 : 1);  // one column in pascals
    b[i] = 0;
    for (size_t j = 0; j < 4; ++j) b[i] += a[i][j] * truth[j];
  }
  const auto r = cal::SolveNnls(a, b);
  CHECK(r.converged);
  for (size_t j = 0; j < 4; ++j) DOUBLES_EQUAL(truth[j], r.x[j], 1e-8 * (1 + truth[j]));
  DOUBLES_EQUAL(0, r.residual_rms, 1e-9);
}

TEST(Nnls, MatchesTheBestActiveSetWhenConstraintsBind) {
  std::mt19937 rng(11);
  std::normal_distribution<double> d(0, 1);
  for (int trial = 0; trial < 30; ++trial) {
    cal::Matrix a(12, std::vector<double>(3));
    std::vector<double> b(12);
    for (size_t i = 0; i < 12; ++i) {
      for (auto& v : a[i]) v = d(rng);
      b[i] = d(rng);
    }
    const auto r = cal::SolveNnls(a, b);
    for (double v : r.x) CHECK(v >= 0);
    // Exhaustive: the best non-negative solution over a fine grid never beats it.
    double best = 1e300;
    for (double x0 = 0; x0 <= 2; x0 += 0.05) {
      for (double x1 = 0; x1 <= 2; x1 += 0.05) {
        for (double x2 = 0; x2 <= 2; x2 += 0.05) best = std::min(best, Cost(a, b, {x0, x1, x2}));
      }
    }
    CHECK(Cost(a, b, r.x) <= best + 1e-9);
  }
}

TEST(Nnls, InterceptIsFreeOfSign) {
  cal::Matrix a;
  std::vector<double> b;
  for (int i = 0; i < 20; ++i) {
    a.push_back({static_cast<double>(i)});
    b.push_back(-7 + 0.5 * i);
  }
  double c = 0;
  const auto r = cal::SolveNnlsWithIntercept(a, b, &c);
  DOUBLES_EQUAL(0.5, r.x[0], 1e-9);
  DOUBLES_EQUAL(-7, c, 1e-9);
}
