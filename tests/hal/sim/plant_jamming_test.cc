// The jamming finger's stiffness against the thesis (fig. 5.36): vacuum, bias, history, presses.
#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/plant_params.h"
#include "plant_test_support.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
namespace params = palpa::sim::params;
using palpa::sim::testing::MakePlant;

TEST_GROUP(JammingStiffness){};

TEST(JammingStiffness, EndPointsAndShapeFollowFig536) {
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  const float tol = params::kTolerancesStiffnessToleranceNPerMm;
  DOUBLES_EQUAL(0.7, j->StaticStiffness(20000, 0), tol);
  DOUBLES_EQUAL(1.3, j->StaticStiffness(20000, -100000), tol);
  float max_slope_bias = 0, max_slope_none = 0;
  for (int v = 0; v < 100; v += 5) {
    const float a = static_cast<float>(-v) * 1000, b = static_cast<float>(-v - 5) * 1000;
    max_slope_bias =
        std::max(max_slope_bias, j->StaticStiffness(20000, b) - j->StaticStiffness(20000, a));
    max_slope_none = std::max(max_slope_none, j->StaticStiffness(0, b) - j->StaticStiffness(0, a));
    CHECK(j->StaticStiffness(20000, b) >= j->StaticStiffness(20000, a));  // monotone
  }
  CHECK(max_slope_none > 2 * max_slope_bias);  // "more abrupt" without bias
}

TEST(JammingStiffness, AirAloneStiffensALittleAndTheCurvesAboveZeroAlmostOverlap) {
  // §5.4.3, Fig 5-36(a): without vacuum, air in the cushion raised the stiffness a little; the
  // curves for 5, 10 and 20 kPa almost overlapped.
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  const float none = j->StaticStiffness(0, 0);
  CHECK_TEXT(j->StaticStiffness(20000, 0) > 1.01f * none, std::to_string(none).c_str());
  CHECK(j->StaticStiffness(20000, 0) < 1.06f * none);  // "a little"
  for (float bias : {5000.0f, 10000.0f}) {
    CHECK(j->StaticStiffness(bias, 0) > 1.01f * none);
    CHECK(std::fabs(j->StaticStiffness(bias, 0) / j->StaticStiffness(20000, 0) - 1) < 0.015f);
  }
}

TEST(JammingStiffness, BiasWidensTheVacuumSpanWhileTheTopBarelyRises) {
  // §5.4.3, §5.5.2: with vacuum, the inflated cushion amplified the stiffness variation and spread
  // the vacuum levels' curves apart, while the maximum force barely rose.
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  auto span = [&](float bias) {
    return j->StaticStiffness(bias, -100000) - j->StaticStiffness(bias, 0);
  };
  CHECK_TEXT(span(20000) > 1.05f * span(0),
             (std::to_string(span(20000)) + " vs " + std::to_string(span(0))).c_str());
  CHECK(span(15000) > span(0) && span(15000) < span(20000));
  const float top = j->StaticStiffness(20000, -100000) / j->StaticStiffness(0, -100000);
  CHECK(top > 1.0f && top < 1.1f);
}

TEST(JammingStiffness, TheBiasAssumptionsSweepAsTheirFactorsSay) {
  auto at = [](float stiffening, float widening, float bias, float vacuum) {
    ps::Effects e;
    e.bias_stiffening = stiffening;
    e.bias_widening = widening;
    ps::Plant plant = MakePlant(2, 0, 1, false, e);
    return plant.jamming(3)->StaticStiffness(bias, vacuum);
  };
  // Anchored at 20 kPa bias: the axis range stays there whatever the factors.
  for (float f : {0.5f, 2.0f}) {
    DOUBLES_EQUAL(0.7, at(f, f, 20000, 0), 1e-4);
    DOUBLES_EQUAL(1.3, at(f, f, 20000, -100000), 1e-4);
  }
  const float rise_half = at(0.5f, 1, 20000, 0) / at(0.5f, 1, 0, 0) - 1;
  const float rise_double = at(2, 1, 20000, 0) / at(2, 1, 0, 0) - 1;
  DOUBLES_EQUAL(4.0, rise_double / rise_half, 0.2);
}

TEST(JammingStiffness, VacuumHistoryShowsWithinItsSweptSize) {
  for (float fraction : {0.05f, 0.1f, 0.2f}) {
    ps::Effects e;
    e.history = fraction;
    ps::Plant plant = MakePlant(2, 0, 1, false, e);
    ps::JammingActuator* j = plant.jamming(3);
    j->Step(20000, -50000);
    const float from_below = j->stiffness();
    j->Step(20000, -100000);
    j->Step(20000, -50000);
    const float from_above = j->stiffness();
    const float effect = (from_above - from_below) / 0.6f;
    CHECK(effect > 0.4f * fraction);
    CHECK(effect <= fraction * 1.001f);
  }
}

TEST(JammingStiffness, PressLoopsStayBelowTheLoadingWorkAndFollowVacuumAndBias) {
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  auto loop = [&](float bias, float vacuum, float& work) {
    j->Step(bias, vacuum);
    double load = 0, unload = 0;
    const int n = 300;
    for (int i = 0; i < n; ++i) {
      const float d = 3.0f * (static_cast<float>(i) + 0.5f) / n;
      load += j->PressForce(d, 3.0f, true) * 3.0 / n;
      unload += j->PressForce(d, 3.0f, false) * 3.0 / n;
      CHECK(j->PressForce(d, 3.0f, false) >= 0);
    }
    work = static_cast<float>(load);
    return static_cast<float>(load - unload);
  };
  float w0 = 0, w1 = 0, w2 = 0, w3 = 0;
  const float at0 = loop(20000, 0, w0), at60 = loop(20000, -60000, w1),
              at100 = loop(20000, -100000, w2);
  const float unbiased100 = loop(0, -100000, w3);
  CHECK(at0 < w0 && at60 < w1 && at100 < w2 && unbiased100 < w3);
  CHECK(at100 / w2 > 1.3f * at60 / w1);                          // loops grow beyond −60 kPa
  DOUBLES_EQUAL(0.35, (at100 / w2) / (unbiased100 / w3), 0.02);  // bias shrinks them by 65 %
}
