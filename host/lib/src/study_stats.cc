// Study statistics: detection metrics, Wilson intervals and the thesis's combined interval, the
// Wilcoxon signed-rank test (exact and normal) and t-tests through the incomplete beta function.
#include "palpa/host/study_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace palpa::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The continued fraction of I_x(a, b) (modified Lentz), converging for x < (a + 1)/(a + b + 2).
double BetaFraction(double x, double a, double b) {
  constexpr double kTiny = 1e-300;
  constexpr double kEps = 1e-16;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m <= 100000; ++m) {
    const double m2 = 2.0 * m;
    // The even step, then the odd one.
    double aa = m * (b - m) * x / ((a + m2 - 1) * (a + m2));
    d = 1 + aa * d;
    c = 1 + aa / c;
    d = 1 / (std::fabs(d) < kTiny ? kTiny : d);
    c = std::fabs(c) < kTiny ? kTiny : c;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1));
    d = 1 + aa * d;
    c = 1 + aa / c;
    d = 1 / (std::fabs(d) < kTiny ? kTiny : d);
    c = std::fabs(c) < kTiny ? kTiny : c;
    const double step = d * c;
    h *= step;
    if (std::fabs(step - 1) < kEps) break;
  }
  return h;
}

double Mean(const std::vector<double>& x) {
  return std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
}

/// The sample variance (n − 1 in the denominator).
double Variance(const std::vector<double>& x, double mean) {
  double sum = 0;
  for (double v : x) sum += (v - mean) * (v - mean);
  return sum / static_cast<double>(x.size() - 1);
}

/// How many of the 2ⁿ sign patterns give each sum of doubled ranks (an integer even with average
/// ranks): the exact null distribution of 2·W₊.
std::vector<double> SignedRankCounts(const std::vector<int>& doubled_ranks) {
  const int total = std::accumulate(doubled_ranks.begin(), doubled_ranks.end(), 0);
  std::vector<double> counts(static_cast<size_t>(total) + 1, 0.0);
  counts[0] = 1;
  int reach = 0;
  for (int r : doubled_ranks) {
    reach += r;
    for (int s = reach; s >= r; --s)
      counts[static_cast<size_t>(s)] += counts[static_cast<size_t>(s - r)];
  }
  return counts;
}

/// Two-sided exact p of an observed 2·W₊ under `counts`: twice the smaller tail, at most 1.
double TwoSidedFromCounts(const std::vector<double>& counts, int observed) {
  const double all = std::accumulate(counts.begin(), counts.end(), 0.0);
  double below = 0, above = 0;
  for (size_t s = 0; s < counts.size(); ++s) {
    if (static_cast<int>(s) <= observed) below += counts[s];
    if (static_cast<int>(s) >= observed) above += counts[s];
  }
  return std::min(1.0, 2 * std::min(below, above) / all);
}

std::vector<int> UntiedDoubledRanks(int n) {
  std::vector<int> ranks(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) ranks[static_cast<size_t>(i)] = 2 * (i + 1);
  return ranks;
}

}  // namespace

DetectionCounts& DetectionCounts::operator+=(const DetectionCounts& o) {
  tp += o.tp;
  fp += o.fp;
  tn += o.tn;
  fn += o.fn;
  return *this;
}

double Proportion::value() const { return n > 0 ? k / n : kNaN; }

Proportion Sensitivity(const DetectionCounts& c) {
  return {static_cast<double>(c.tp), static_cast<double>(c.tp + c.fn)};
}
Proportion Specificity(const DetectionCounts& c) {
  return {static_cast<double>(c.tn), static_cast<double>(c.tn + c.fp)};
}
Proportion Precision(const DetectionCounts& c) {
  return {static_cast<double>(c.tp), static_cast<double>(c.tp + c.fp)};
}
Proportion Accuracy(const DetectionCounts& c) {
  return {static_cast<double>(c.tp + c.tn), static_cast<double>(c.total())};
}

Interval WilsonInterval(Proportion p, double z) {
  if (!(p.n > 0)) return {kNaN, kNaN};
  const double n = p.n, q = p.value(), z2 = z * z;
  const double centre = q + z2 / (2 * n);
  const double half = z * std::sqrt(q * (1 - q) / n + z2 / (4 * n * n));
  const double scale = 1 + z2 / n;
  return {(centre - half) / scale, (centre + half) / scale};
}

ProportionComparison CompareProportions(Proportion first, Proportion second, double z) {
  ProportionComparison c;
  const double p1 = first.value(), p2 = second.value();
  c.difference = p2 - p1;
  if (std::isnan(c.difference)) {
    c.combined = kNaN;
    return c;
  }
  // The lower proportion's upper bound, the higher one's lower bound.
  const bool first_lower = p1 <= p2;
  const Proportion& low = first_lower ? first : second;
  const Proportion& high = first_lower ? second : first;
  const double upper_of_low = WilsonInterval(low, z).hi;
  const double lower_of_high = WilsonInterval(high, z).lo;
  c.combined = std::hypot(low.value() - upper_of_low, high.value() - lower_of_high);
  c.significant = std::fabs(c.difference) > c.combined;
  return c;
}

WilcoxonResult WilcoxonSignedRank(const std::vector<double>& first,
                                  const std::vector<double>& second) {
  WilcoxonResult r;
  if (first.size() != second.size()) {
    r.p = kNaN;
    return r;
  }
  std::vector<double> d;
  for (size_t i = 0; i < first.size(); ++i) {
    if (second[i] != first[i]) d.push_back(second[i] - first[i]);
  }
  r.n = static_cast<int>(d.size());
  if (r.n == 0) return r;  // nothing differs: no evidence either way, p = 1
  std::vector<size_t> order(d.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return std::fabs(d[a]) < std::fabs(d[b]); });
  // Average ranks over ties, kept doubled (integers) for the exact distribution.
  std::vector<int> doubled(d.size());
  double tie_term = 0;
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && std::fabs(d[order[j + 1]]) == std::fabs(d[order[i]])) ++j;
    const auto group = static_cast<double>(j - i + 1);
    tie_term += group * group * group - group;
    for (size_t k = i; k <= j; ++k) doubled[order[k]] = static_cast<int>(i + j + 2);  // 2·avg
    i = j + 1;
  }
  int doubled_plus = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    (d[i] > 0 ? r.w_plus : r.w_minus) += doubled[i] / 2.0;
    if (d[i] > 0) doubled_plus += doubled[i];
  }
  r.w = std::fabs(r.w_plus - r.w_minus);
  r.t = std::min(r.w_plus, r.w_minus);
  const double n = r.n;
  const double mean = n * (n + 1) / 4;
  const double sd = std::sqrt(n * (n + 1) * (2 * n + 1) / 24 - tie_term / 48);
  r.z = (r.t - mean) / sd;
  r.exact = r.n <= kWilcoxonExactMax;
  r.p = r.exact ? TwoSidedFromCounts(SignedRankCounts(doubled), doubled_plus)
                : std::min(1.0, 2 * NormalCdf(-std::fabs(r.z)));
  r.critical_t = WilcoxonCriticalT(r.n);
  r.significant_by_table = r.critical_t >= 0 && r.t <= r.critical_t;
  return r;
}

double WilcoxonExactP(int n, double t) {
  if (n <= 0) return 1;
  if (n > kWilcoxonExactMax) {
    const double mean = n * (n + 1.0) / 4, sd = std::sqrt(n * (n + 1.0) * (2.0 * n + 1) / 24);
    return std::min(1.0, 2 * NormalCdf((std::floor(t) - mean) / sd));
  }
  const std::vector<double> counts = SignedRankCounts(UntiedDoubledRanks(n));
  return TwoSidedFromCounts(counts, static_cast<int>(std::floor(2 * t)));
}

int WilcoxonCriticalT(int n) {
  if (n <= 0) return -1;
  if (n > kWilcoxonExactMax) {  // printed tables stop well before: the normal approximation's
    const double mean = n * (n + 1.0) / 4, sd = std::sqrt(n * (n + 1.0) * (2.0 * n + 1) / 24);
    return static_cast<int>(std::floor(mean - kZ95 * sd));
  }
  const std::vector<double> counts = SignedRankCounts(UntiedDoubledRanks(n));
  const double all = std::ldexp(1.0, n);
  double below = 0;
  int critical = -1;
  for (int t = 0; 2 * t < static_cast<int>(counts.size()); ++t) {
    below += counts[static_cast<size_t>(2 * t)];
    if (2 * below / all > 0.05) break;
    critical = t;
  }
  return critical;
}

TTestResult PairedTTest(const std::vector<double>& first, const std::vector<double>& second) {
  TTestResult r;
  if (first.size() != second.size() || first.size() < 2) {
    r.t = r.p = kNaN;
    return r;
  }
  std::vector<double> d(first.size());
  for (size_t i = 0; i < d.size(); ++i) d[i] = second[i] - first[i];
  r.mean_difference = Mean(d);
  const auto n = static_cast<double>(d.size());
  r.df = n - 1;
  r.t = r.mean_difference / std::sqrt(Variance(d, r.mean_difference) / n);
  r.p = StudentTwoSidedP(r.t, r.df);
  return r;
}

TTestResult WelchTTest(const std::vector<double>& first, const std::vector<double>& second) {
  TTestResult r;
  if (first.size() < 2 || second.size() < 2) {
    r.t = r.p = kNaN;
    return r;
  }
  const double m1 = Mean(first), m2 = Mean(second);
  const double v1 = Variance(first, m1) / static_cast<double>(first.size());
  const double v2 = Variance(second, m2) / static_cast<double>(second.size());
  r.mean_difference = m2 - m1;
  r.t = r.mean_difference / std::sqrt(v1 + v2);
  r.df = (v1 + v2) * (v1 + v2) /
         (v1 * v1 / static_cast<double>(first.size() - 1) +
          v2 * v2 / static_cast<double>(second.size() - 1));
  r.p = StudentTwoSidedP(r.t, r.df);
  return r;
}

double StudentTwoSidedP(double t, double df) {
  if (std::isnan(t) || !(df > 0)) return kNaN;
  if (std::isinf(t)) return 0;
  return RegularizedBeta(df / (df + t * t), df / 2, 0.5);
}

double RegularizedBeta(double x, double a, double b) {
  if (!(x >= 0 && x <= 1) || !(a > 0) || !(b > 0)) return kNaN;
  if (x == 0 || x == 1) return x;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  // The fraction converges quickly only below the mean; above it, by symmetry.
  if (x < (a + 1) / (a + b + 2)) return front * BetaFraction(x, a, b) / a;
  return 1 - front * BetaFraction(1 - x, b, a) / b;
}

double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace palpa::host
