// Identification: PI recovered from its own data, api beating pi on an asymmetric loop, branch
// curves from a major loop, the sweep design, and bad sweeps refused with the point named.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "palpa/calibration/hysteresis_fit.h"
#include "palpa/calibration/play_operators.h"
#include "palpa/calibration/sweep.h"
#include "palpa/core/compensator.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

std::vector<cal::SweepSample> Measure(const cal::PlayModel& m, const std::vector<double>& u,
                                      double noise = 0, uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, noise > 0 ? noise : 1);
  const auto y = m.Simulate(u);
  std::vector<cal::SweepSample> s;
  for (size_t k = 0; k < u.size(); ++k) s.push_back({u[k], y[k] + (noise > 0 ? n(rng) : 0)});
  return s;
}

cal::PlayModel TruthPi() {
  cal::PlayModel m;
  m.offset = 40;
  m.w0 = 0.01;
  m.thresholds = cal::EvenThresholds(8, 100000);
  m.weights = {0.004, 0.003, 0.002, 0.002, 0.001, 0.001, 0.0005, 0.0005};
  return m;
}

}  // namespace

TEST_GROUP(HysteresisFit) { std::vector<double> drives = cal::SweepDrives(cal::SweepPlan{}); };

TEST(HysteresisFit, SweepStartsVentedRunsTheMajorLoopAndNestsReversals) {
  DOUBLES_EQUAL(0, drives.front(), 0);
  DOUBLES_EQUAL(0, drives.back(), 0);
  DOUBLES_EQUAL(100000, *std::max_element(drives.begin(), drives.end()), 0);
  int reversals = 0;
  for (size_t k = 2; k < drives.size(); ++k) {
    if ((drives[k] - drives[k - 1]) * (drives[k - 1] - drives[k - 2]) < 0) ++reversals;
  }
  LONGS_EQUAL(1 + 2 * 4, reversals);  // top of the major loop, then 4 nested pairs
}

TEST(HysteresisFit, PiRecoversItsOwnModelAndTheFirmwareInvertsIt) {
  const auto truth = TruthPi();
  const auto sweep = Measure(truth, drives);
  const cal::HysteresisFit fit = cal::FitPi(sweep, 8, 100000);
  CHECK_TEXT(fit.ok(), fit.error.c_str());
  CHECK(fit.residual_rms < 1e-3);
  // The firmware compensator, fed the fitted parameters, asks for the drive that produced each
  // output of a held-out drive sequence.
  pp::ConfigureFinger f{};
  CHECK(cal::ApplyFit(fit, f).ok());
  const pc::Compensator c = pc::MakeCompensator(f, 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(0, 100000);
  std::vector<double> held_out{0};
  for (int k = 0; k < 300; ++k) held_out.push_back(d(rng));
  const auto y = truth.Simulate(held_out);
  for (size_t k = 1; k < held_out.size(); ++k) {
    const auto out =
        pc::StepCompensator(c, s, static_cast<float>(y[k]), static_cast<float>(held_out[k - 1]));
    DOUBLES_EQUAL(held_out[k], out.drive, 30);  // Pa, float arithmetic
  }
}

TEST(HysteresisFit, EveryOperatorAddsADegreeOfFreedomOnTheSweepsPalpaUses) {
  // An operator with threshold 0 is the drive itself (w0·u again); one at half the range or above
  // never leaves its vented clamp under a one-sided drive, a constant like the offset.
  const auto u = cal::SweepDrives(cal::SweepPlan{100000, 5000, 4});  // palpa calibrate, pneumatic
  LONGS_EQUAL(2, cal::DistinctOperators(u, {0, 20000, 30000}));
  LONGS_EQUAL(2, cal::DistinctOperators(u, {10000, 20000, 50000}));
  LONGS_EQUAL(2, cal::DistinctOperators(u, {10000, 20000, 20000}));
  // Thresholds sit strictly inside (0, half the range), evenly.
  for (int n : {1, 4, 8, 16, 32}) {
    const auto r = cal::EvenThresholds(n, 100000);
    LONGS_EQUAL(n, r.size());
    CHECK(r.front() > 0);
    CHECK(r.back() < 50000);
    for (size_t i = 1; i < r.size(); ++i) DOUBLES_EQUAL(r[0], r[i] - r[i - 1], 1e-9);
  }
  // Each sweep with the sizes fitted on it: the benchmark's (2.5 kPa), the calibration's
  // (pneumatic 5 kPa, --quick 10 kPa; jamming --quick 10 kPa), every operator its own.
  struct Use {
    cal::SweepPlan plan;
    int most;
  };
  for (const Use& use :
       {Use{cal::SweepPlan{100000, 2500, 4}, 32}, Use{cal::SweepPlan{100000, 5000, 4}, 16},
        Use{cal::SweepPlan{100000, 10000, 2}, 8}, Use{cal::SweepPlan{100000, 10000, 1}, 8}}) {
    const auto staircase = cal::SweepDrives(use.plan);
    for (int n = 1; n <= use.most; n *= 2) {
      LONGS_EQUAL_TEXT(n, cal::DistinctOperators(staircase, cal::EvenThresholds(n, 100000)),
                       ("step " + std::to_string(use.plan.step)).c_str());
    }
  }
  // A coarse staircase cannot tell close thresholds apart: the jamming finger's 10 kPa sweep has
  // room for 9 of 16.
  const auto jamming = cal::SweepDrives(cal::SweepPlan{100000, 10000, 2});
  LONGS_EQUAL(9, cal::DistinctOperators(jamming, cal::EvenThresholds(16, 100000)));
  LONGS_EQUAL(9, cal::OperatorsToldApart(jamming, 100000, 16));
  LONGS_EQUAL(16, cal::OperatorsToldApart(u, 100000, 16));
}

TEST(HysteresisFit, AFitSaysHowManyOfItsOperatorsCarryAWeight) {
  const auto sweep = Measure(TruthPi(), drives);
  for (int n : {4, 16}) {
    const auto fit = cal::FitPi(sweep, n, 100000);
    CHECK_TEXT(fit.ok(), fit.error.c_str());
    LONGS_EQUAL(n, fit.operators);
    // The weights as the board gets them: params = offset, w0, n thresholds, n weights.
    int nonzero = 0;
    for (int i = 0; i < n; ++i) nonzero += fit.params[static_cast<size_t>(2 + n + i)] != 0;
    LONGS_EQUAL(nonzero, fit.operators_used);
    CHECK(fit.operators_used >= 1);
  }
  // Sweep lengths: what a fit needs, and the most operators a sweep of a given length allows.
  LONGS_EQUAL(36, cal::MinSweepPoints(pp::CompensatorKind::kPrandtlIshlinskii, 16));
  LONGS_EQUAL(28, cal::MinSweepPoints(pp::CompensatorKind::kAsymmetricPi, 8));
  LONGS_EQUAL(12, cal::MaxOperators(pp::CompensatorKind::kPrandtlIshlinskii, 28));
  LONGS_EQUAL(8, cal::MaxOperators(pp::CompensatorKind::kAsymmetricPi, 28));
  LONGS_EQUAL(32, cal::MaxOperators(pp::CompensatorKind::kPrandtlIshlinskii, 1000));
  LONGS_EQUAL(0, cal::MaxOperators(pp::CompensatorKind::kAsymmetricPi, 10));
  const auto short_fit =
      cal::FitPi(std::vector<cal::SweepSample>(sweep.begin(), sweep.begin() + 35), 16, 100000);
  CHECK(short_fit.error.find("at least 36") != std::string::npos);
}

TEST(HysteresisFit, AsymmetricLoopsNeedApi) {
  cal::PlayModel truth = TruthPi();
  truth.dead_zones = {300, 800};
  truth.gains = {0.8, -1.2};  // steeper mid-range, flatter at the top: not point-symmetric
  const auto sweep = Measure(truth, drives);
  const auto pi = cal::FitPi(sweep, 8, 100000);
  const auto api = cal::FitApi(sweep, 8, 4, 100000);
  CHECK_TEXT(api.ok(), api.error.c_str());
  CHECK(api.residual_rms < 0.5 * pi.residual_rms);
}

TEST(HysteresisFit, BranchCurvesComeFromTheMajorLoop) {
  const auto truth = TruthPi();
  const auto sweep = Measure(truth, drives);
  const auto fit = cal::FitBranch(sweep, 12);
  CHECK_TEXT(fit.ok(), fit.error.c_str());
  // On the major rising pass the rising curve gives the drive back.
  pp::ConfigureFinger f{};
  CHECK(cal::ApplyFit(fit, f).ok());
  const pc::Compensator c = pc::MakeCompensator(f, 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  const auto y = truth.Simulate({0, 50000});
  DOUBLES_EQUAL(50000, pc::StepCompensator(c, s, static_cast<float>(y[1]), 0).drive, 1500);
  const auto fitted = cal::FitStaticInverse(sweep, 10, false);
  const auto& inverse = fitted.value;
  CHECK_TEXT(fitted.ok() && inverse.size() >= 8, fitted.message.c_str());
  for (size_t k = 1; k < inverse.size(); ++k) CHECK(inverse[k].output > inverse[k - 1].output);
}

TEST(HysteresisFit, FewAndNoisyPointsStillGiveAnInvertibleModel) {
  // 5 points per branch and 10 % noise: worse, but never a set the firmware would refuse.
  const auto truth = TruthPi();
  const auto coarse = cal::SweepDrives(cal::SweepPlan{100000, 20000, 2});
  const auto sweep = Measure(truth, coarse, 0.1 * 700, 9);
  for (int n : {4, 8}) {
    const auto fit = cal::FitPi(sweep, n, 100000);
    CHECK_TEXT(fit.ok(), fit.error.c_str());
    CHECK(std::isfinite(fit.residual_rms));
  }
  const auto too_few = cal::FitPi(sweep, 32, 100000);
  CHECK_FALSE(too_few.ok());
  CHECK(too_few.error.find("at least") != std::string::npos);
}

TEST(HysteresisFit, BadSweepsAreRefusedWithThePointNamed) {
  auto sweep = Measure(TruthPi(), drives);
  sweep[17].output = std::nan("");
  auto fit = cal::FitPi(sweep, 8, 100000);
  CHECK_FALSE(fit.ok());
  CHECK(fit.error.find("point 17") != std::string::npos);
  sweep[17].output = 1;
  sweep[30].drive_pa = 250000;
  fit = cal::FitApi(sweep, 8, 2, 100000);
  CHECK(fit.error.find("point 30") != std::string::npos);
  CHECK_FALSE(cal::FitBranch({{0, 0}, {1, 1}}, 12).ok());
}
