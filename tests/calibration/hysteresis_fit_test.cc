// Identification: PI recovered from its own data, api beating pi on an asymmetric loop, branch
// curves from a major loop, the sweep design, and bad sweeps refused with the point named.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "palpa/calibration/hysteresis_fit.h"
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
  CHECK(cal::ApplyFit(fit, f, nullptr));
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
  CHECK(cal::ApplyFit(fit, f, nullptr));
  const pc::Compensator c = pc::MakeCompensator(f, 100000);
  pc::CompensatorState s;
  pc::HomeCompensator(c, s);
  const auto y = truth.Simulate({0, 50000});
  DOUBLES_EQUAL(50000, pc::StepCompensator(c, s, static_cast<float>(y[1]), 0).drive, 1500);
  std::string error;
  const auto inverse = cal::FitStaticInverse(sweep, 10, false, &error);
  CHECK_TEXT(inverse.size() >= 8, error.c_str());
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
