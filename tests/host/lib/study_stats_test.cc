// Study statistics against the thesis's own figures (§3, §5, checked in the reference), a
// published Wilcoxon table and t quantiles; study_stats_scipy.py compares every statistic with
// scipy on random inputs.
#include "palpa/host/study_stats.h"

#include <cmath>

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;

namespace {

ph::Proportion Of(double percent, double n) { return {percent / 100 * n, n}; }

}  // namespace

TEST_GROUP(StudyStats){};

TEST(StudyStats, MetricsCountEachFingerPosition) {
  const ph::DetectionCounts c{40, 5, 50, 10};  // TP, FP, TN, FN
  DOUBLES_EQUAL(40.0 / 50, ph::Sensitivity(c).value(), 1e-15);
  DOUBLES_EQUAL(50.0 / 55, ph::Specificity(c).value(), 1e-15);
  DOUBLES_EQUAL(40.0 / 45, ph::Precision(c).value(), 1e-15);
  DOUBLES_EQUAL(90.0 / 105, ph::Accuracy(c).value(), 1e-15);
  CHECK_EQUAL(50.0, ph::Sensitivity(c).n);
  CHECK(std::isnan(ph::Precision({0, 0, 3, 2}).value()));  // nothing marked: no PPV
  CHECK(std::isnan(ph::WilsonInterval({0, 0}).lo));
}

TEST(StudyStats, WilsonIntervalsAsTheThesisPrintsThem) {
  ph::Interval i = ph::WilsonInterval({55, 60});  // thesis: 82.0–96.4 % (81.93 rounds to 81.9)
  DOUBLES_EQUAL(0.8193, i.lo, 5e-5);
  DOUBLES_EQUAL(0.9639, i.hi, 5e-5);
  i = ph::WilsonInterval({20, 30});  // 48.8–80.8 %
  DOUBLES_EQUAL(0.4878, i.lo, 5e-5);
  DOUBLES_EQUAL(0.8077, i.hi, 5e-5);
  i = ph::WilsonInterval({54, 60});  // 79.9–95.3 %
  DOUBLES_EQUAL(0.7985, i.lo, 5e-5);
  DOUBLES_EQUAL(0.9534, i.hi, 5e-5);
  // At the ends the interval stays inside 0 … 1 and is not empty.
  i = ph::WilsonInterval({0, 12});
  DOUBLES_EQUAL(0, i.lo, 1e-15);
  CHECK(i.hi > 0.2 && i.hi < 0.3);
}

TEST(StudyStats, CombinedIntervalAgainstTheDifference) {
  // 53/60 against 55/60: combined 0.114 > difference 0.033, not significant (thesis §3).
  ph::ProportionComparison c = ph::CompareProportions({53, 60}, {55, 60});
  DOUBLES_EQUAL(0.1138, c.combined, 5e-5);
  DOUBLES_EQUAL(2.0 / 60, c.difference, 1e-15);
  CHECK_FALSE(c.significant);
  // Either order gives the same interval; the difference keeps its sign.
  const ph::ProportionComparison back = ph::CompareProportions({55, 60}, {53, 60});
  DOUBLES_EQUAL(c.combined, back.combined, 1e-15);
  DOUBLES_EQUAL(-c.difference, back.difference, 1e-15);
  // Force against visual feedback, Table 3-2: CI 0.225 (0.2255), from 20 and 23 of 30 — the one
  // pair of counts out of 30 with 20/30 (the thesis's own Wilson example) that gives it.
  c = ph::CompareProportions({20, 30}, {23, 30});
  DOUBLES_EQUAL(0.2255, c.combined, 5e-5);
  CHECK_FALSE(c.significant);
}

TEST(StudyStats, ChapterFiveComparisonsWithTheThesisN) {
  // The thesis's intervals come out with n = every finger position (504, 192) for each metric;
  // the percentages are all it prints (to 0.1 %), so they stand in for the counts, and the
  // intervals agree to its last digit (0.0745 is printed 0.074).
  struct Row {
    double single, multi, n, combined;  // %, %, n, the printed interval (0 when not printed)
    bool significant;
  };
  const Row rows[] = {
      {88.2, 93.5, 504, 0, true},      {94.1, 96.8, 504, 0.026, true},   // pneumatic Se, Sp
      {91.4, 96.9, 504, 0, true},      {93.3, 96.8, 504, 0.027, true},   // PPV, ACC
      {76.4, 82.2, 192, 0.081, false}, {85.7, 88.9, 192, 0.067, false},  // jamming Se, Sp
      {75.3, 80.0, 192, 0.083, false}, {81.8, 85.4, 192, 0.074, false},  // PPV, ACC
  };
  for (const Row& r : rows) {
    const ph::ProportionComparison c = ph::CompareProportions(Of(r.single, r.n), Of(r.multi, r.n));
    if (r.combined > 0) DOUBLES_EQUAL(r.combined, c.combined, 1e-3);
    CHECK_EQUAL(r.significant, c.significant);
  }
}

TEST(StudyStats, WilcoxonCriticalValuesMatchThePublishedTable) {
  // T (the smaller rank sum) at α = 0.05 two-sided, n = 6 … 30, as printed tables give it.
  const int published[] = {0,  2,  3,  5,  8,  10, 13, 17, 21,  25,  29,  34, 40,
                           46, 52, 58, 65, 73, 81, 89, 98, 107, 116, 126, 137};
  CHECK_EQUAL(-1, ph::WilcoxonCriticalT(5));
  for (int n = 6; n <= 30; ++n) CHECK_EQUAL(published[n - 6], ph::WilcoxonCriticalT(n));
  // Beyond the exact range, the normal approximation's: floor(2525 − 1.96 × 290.84) = 1954.
  CHECK_EQUAL(1954, ph::WilcoxonCriticalT(100));
  // Each critical value is the last whose exact p stays at or under 0.05.
  for (int n = 6; n <= 30; ++n) {
    CHECK(ph::WilcoxonExactP(n, ph::WilcoxonCriticalT(n)) <= 0.05);
    CHECK(ph::WilcoxonExactP(n, ph::WilcoxonCriticalT(n) + 1) > 0.05);
  }
}

TEST(StudyStats, WilcoxonByHand) {
  // Differences 1, −2, 3, 4, 4, 6, 0: the zero dropped, the two 4s share rank 4.5.
  const std::vector<double> first = {10, 10, 10, 10, 10, 10, 10};
  const std::vector<double> second = {11, 8, 13, 14, 14, 16, 10};
  const ph::WilcoxonResult w = ph::WilcoxonSignedRank(first, second);
  CHECK_EQUAL(6, w.n);
  DOUBLES_EQUAL(2, w.w_minus, 1e-15);
  DOUBLES_EQUAL(1 + 3 + 4.5 + 4.5 + 6, w.w_plus, 1e-15);
  DOUBLES_EQUAL(17, w.w, 1e-15);  // the thesis's |Σ sgn·R|
  DOUBLES_EQUAL(2, w.t, 1e-15);
  CHECK_TRUE(w.exact);
  // Sign patterns of the 2⁶ with W₊ ≥ 19: all positive (21), all but rank 1 (20), all but rank 2
  // (19) — 3, doubled for both tails.
  DOUBLES_EQUAL(2.0 * 3 / 64, w.p, 1e-15);
  CHECK_EQUAL(0, w.critical_t);
  CHECK_FALSE(w.significant_by_table);
  // Every pair differing one way: the smallest exact p for n = 8 (2/256).
  const ph::WilcoxonResult all =
      ph::WilcoxonSignedRank({1, 2, 3, 4, 5, 6, 7, 8}, {2, 4, 6, 8, 10, 12, 14, 16});
  DOUBLES_EQUAL(2.0 / 256, all.p, 1e-15);
  CHECK_TRUE(all.significant_by_table);
  CHECK(std::isnan(ph::WilcoxonSignedRank({1, 2}, {1}).p));
}

TEST(StudyStats, StudentTAtItsQuantiles) {
  DOUBLES_EQUAL(0.05, ph::StudentTwoSidedP(2.228138851986274, 10), 1e-12);
  DOUBLES_EQUAL(0.05, ph::StudentTwoSidedP(-12.70620473617471, 1), 1e-12);
  DOUBLES_EQUAL(0.01, ph::StudentTwoSidedP(2.749995653567845, 30), 1e-12);
  DOUBLES_EQUAL(1, ph::StudentTwoSidedP(0, 5), 1e-15);
  // Paired: differences 1, 2, 3 → mean 2, sd 1, t = 2·√3.
  const ph::TTestResult paired = ph::PairedTTest({0, 0, 0}, {1, 2, 3});
  DOUBLES_EQUAL(2 * std::sqrt(3.0), paired.t, 1e-12);
  DOUBLES_EQUAL(2, paired.df, 0);
  // Welch with equal sizes and variances: df = 2n − 2 and the pooled t.
  const ph::TTestResult welch = ph::WelchTTest({1, 2, 3, 4}, {3, 4, 5, 6});
  DOUBLES_EQUAL(6, welch.df, 1e-12);
  DOUBLES_EQUAL(2 / std::sqrt(5.0 / 3 / 2), welch.t, 1e-12);
  CHECK(std::isnan(ph::WelchTTest({1}, {2, 3}).p));
}
