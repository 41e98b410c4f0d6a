// Prints the library's statistics for seeded random inputs, one JSON object per line (inputs and
// results), for study_stats_scipy.py to recompute with scipy.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/study_stats.h"

namespace ph = palpa::host;
using nlohmann::json;

namespace {

std::mt19937_64 g_random(20261126);

int Uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g_random); }

std::vector<double> Sample(int n, double mean, double sd, bool integers) {
  std::normal_distribution<double> normal(mean, sd);
  std::vector<double> x(static_cast<size_t>(n));
  for (double& v : x) v = integers ? std::round(normal(g_random)) : normal(g_random);
  return x;
}

void Print(const json& j) { std::printf("%s\n", j.dump().c_str()); }

}  // namespace

int main() {
  for (int i = 0; i < 300; ++i) {
    const int n = Uniform(1, 600), k = Uniform(0, n);
    const ph::Interval w = ph::WilsonInterval({double(k), double(n)});
    Print({{"test", "wilson"}, {"k", k}, {"n", n}, {"lo", w.lo}, {"hi", w.hi}});
  }
  for (int i = 0; i < 200; ++i) {
    const int n1 = Uniform(1, 300), n2 = Uniform(1, 300);
    const int k1 = Uniform(0, n1), k2 = Uniform(0, n2);
    const ph::ProportionComparison c =
        ph::CompareProportions({double(k1), double(n1)}, {double(k2), double(n2)});
    Print({{"test", "combined"},
           {"k1", k1},
           {"n1", n1},
           {"k2", k2},
           {"n2", n2},
           {"difference", c.difference},
           {"combined", c.combined},
           {"significant", c.significant}});
  }
  for (int i = 0; i < 240; ++i) {
    // Small integer samples tie and repeat; continuous ones do not. Up to 80 pairs: both the
    // exact and the normal p.
    const bool integers = i % 2 == 0;
    const int n = Uniform(1, i < 200 ? 50 : 80);
    const std::vector<double> first = Sample(n, 10, integers ? 2 : 1, integers);
    const std::vector<double> second =
        Sample(n, 10 + Uniform(0, 2) * 0.5, integers ? 2 : 1, integers);
    const ph::WilcoxonResult w = ph::WilcoxonSignedRank(first, second);
    Print({{"test", "wilcoxon"},
           {"first", first},
           {"second", second},
           {"n", w.n},
           {"t", w.t},
           {"w", w.w},
           {"w_plus", w.w_plus},
           {"z", w.z},
           {"p", w.p},
           {"exact", w.exact}});
  }
  for (int n = 1; n <= 50; ++n)
    Print({{"test", "critical"}, {"n", n}, {"critical_t", ph::WilcoxonCriticalT(n)}});
  for (int i = 0; i < 200; ++i) {
    // Effects from none to many standard errors: p from 1 down to far below 1e-30.
    const int n = Uniform(2, 200);
    const double shift = i % 4 == 0 ? 0.0 : Uniform(0, 60) * 0.1;
    const std::vector<double> first = Sample(n, 5, 1, false);
    std::vector<double> second = Sample(n, 5 + shift, Uniform(1, 3), false);
    const ph::TTestResult paired = ph::PairedTTest(first, second);
    const std::vector<double> paired_second = second;
    if (i % 2 == 1) second.resize(static_cast<size_t>(Uniform(2, n < 3 ? 2 : n)));
    const ph::TTestResult welch = ph::WelchTTest(first, second);
    Print({{"test", "ttest"},
           {"first", first},
           {"second", second},
           {"paired_second", paired_second},
           {"paired", {{"t", paired.t}, {"df", paired.df}, {"p", paired.p}}},
           {"welch", {{"t", welch.t}, {"df", welch.df}, {"p", welch.p}}}});
  }
  for (int i = 0; i < 200; ++i) {
    const double x = std::uniform_real_distribution<double>(0, 1)(g_random);
    const double a = std::exp(std::uniform_real_distribution<double>(-3, 6)(g_random));
    const double b = std::exp(std::uniform_real_distribution<double>(-3, 6)(g_random));
    Print(
        {{"test", "beta"}, {"x", x}, {"a", a}, {"b", b}, {"value", ph::RegularizedBeta(x, a, b)}});
  }
  return 0;
}
