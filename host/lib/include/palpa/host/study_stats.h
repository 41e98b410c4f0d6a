// The statistics of discrimination studies, as the thesis used them (§3, §5): detection metrics
// from TP/FP/TN/FN, Wilson score intervals (eq 3.5), the combined interval of two proportions
// (eq 3.6), the Wilcoxon signed-rank test (eq 3.7) and Student's t-tests, with exact p-values where
// the thesis read a table. Formulas and how to read them: docs/studies.md, "Analysis".
#pragma once

#include <cstdint>
#include <vector>

namespace palpa::host {

/// The normal distribution's 0.975 quantile: a two-sided 95 % interval.
inline constexpr double kZ95 = 1.959963984540054;

/// Finger positions classified against the truth (each finger position of each trial is one).
struct DetectionCounts {
  int64_t tp = 0, fp = 0, tn = 0, fn = 0;
  int64_t total() const { return tp + fp + tn + fn; }
  DetectionCounts& operator+=(const DetectionCounts& o);
};

/// k successes out of n (n may be 0: no value).
struct Proportion {
  double k = 0, n = 0;   ///< counts; doubles so a printed percentage of n can be compared too
  double value() const;  ///< k / n; NaN when n is 0
};

Proportion Sensitivity(const DetectionCounts& c);  ///< TP / (TP + FN), eq 3.4
Proportion Specificity(const DetectionCounts& c);  ///< TN / (TN + FP), eq 4.19
Proportion Precision(const DetectionCounts& c);    ///< PPV: TP / (TP + FP), eq 4.16
Proportion Accuracy(const DetectionCounts& c);     ///< (TP + TN) / all, eq 4.20

struct Interval {
  double lo = 0, hi = 0;
};

/// Wilson score interval of a proportion (eq 3.5); NaN bounds when n is 0.
Interval WilsonInterval(Proportion p, double z = kZ95);

/// The thesis's comparison of two proportions (eq 3.6): the lower one's upper Wilson bound and the
/// higher one's lower bound, combined as sqrt((p₁ − P₁)² + (p₂ − P₂)²); the difference is called
/// significant when |p₁ − p₂| exceeds it.
struct ProportionComparison {
  double difference = 0;  ///< p₂ − p₁ (second minus first), signed
  double combined = 0;    ///< the combined interval
  bool significant = false;
};
ProportionComparison CompareProportions(Proportion first, Proportion second, double z = kZ95);

/// Wilcoxon signed-rank test on pairs (x₁ᵢ, x₂ᵢ): differences x₂ − x₁, zeros dropped, |d| ranked
/// with average ranks for ties.
struct WilcoxonResult {
  int n = 0;                       ///< non-zero pairs (the thesis's n_r)
  double w_plus = 0, w_minus = 0;  ///< rank sums of the positive and negative differences
  double w = 0;         ///< |Σ sgn(dᵢ)·Rᵢ| = |W₊ − W₋|, the thesis's W (eq 3.7)
  double t = 0;         ///< min(W₊, W₋): the statistic tables and scipy give
  double p = 1;         ///< two-sided
  bool exact = false;   ///< p from the exact distribution, not the normal one
  double z = 0;         ///< the normal approximation's z (tie-corrected)
  int critical_t = -1;  ///< α = 0.05 two-sided: significant when t ≤ this; −1 none
  bool significant_by_table = false;  ///< t ≤ critical_t (without ties: p ≤ 0.05)
};
/// Exact p-value (the permutation distribution of the ranks, ties' average ranks included) for up
/// to kWilcoxonExactMax non-zero pairs; beyond it the normal approximation with the tie correction
/// and no continuity correction. Pairs of unequal length: empty result with p = NaN.
inline constexpr int kWilcoxonExactMax = 50;
WilcoxonResult WilcoxonSignedRank(const std::vector<double>& first,
                                  const std::vector<double>& second);

/// The α = 0.05 two-sided critical value of T = min(W₊, W₋) for n pairs without ties: the largest
/// t with P(T ≤ t) ≤ 0.05 under the exact distribution, as printed tables give it; −1 when no t is
/// small enough (n ≤ 5). Beyond kWilcoxonExactMax pairs, from the normal approximation.
int WilcoxonCriticalT(int n);
/// Two-sided exact p of T = min(W₊, W₋) ≤ t for n untied pairs (the table's distribution); beyond
/// kWilcoxonExactMax pairs, the normal approximation's.
double WilcoxonExactP(int n, double t);

struct TTestResult {
  double t = 0;                ///< (mean₂ − mean₁) over its standard error
  double df = 0;               ///< degrees of freedom (Welch–Satterthwaite for Welch)
  double p = 1;                ///< two-sided
  double mean_difference = 0;  ///< mean₂ − mean₁
};
/// Paired t-test on x₂ − x₁ (at least two pairs; else p = NaN).
TTestResult PairedTTest(const std::vector<double>& first, const std::vector<double>& second);
/// Welch's t-test (unequal variances) of the second sample against the first (≥ 2 values each).
TTestResult WelchTTest(const std::vector<double>& first, const std::vector<double>& second);

/// Student's t distribution: P(|T| ≥ |t|) with df degrees of freedom (through the regularised
/// incomplete beta function; accurate far into the tail, e.g. 1e-30).
double StudentTwoSidedP(double t, double df);
/// The regularised incomplete beta function I_x(a, b).
double RegularizedBeta(double x, double a, double b);
/// P(Z ≤ z) for the standard normal.
double NormalCdf(double z);

}  // namespace palpa::host
