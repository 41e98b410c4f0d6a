// The rig's measurements: close to the truth, never equal to it, with the errors the rig's
// sensors explain (contact-detection jitter, force noise in the press regression).
#include <cmath>

#include "palpa/hal/sim/rig_measurement.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;

TEST_GROUP(RigMeasurement){};

TEST(RigMeasurement, DeformationByContactDetectionHasJitterButNoBiasAfterZeroing) {
  ps::RigMeasurement rig(3);
  rig.Zero(0);
  double sum = 0, sum2 = 0;
  int exact = 0;
  for (int k = 0; k < 200; ++k) {
    const float truth = 0.5f + 0.01f * static_cast<float>(k % 50);
    const double e = rig.Deformation(truth) - truth;
    sum += e;
    sum2 += e * e;
    exact += e == 0;
  }
  const double mean = sum / 200, sd = std::sqrt(sum2 / 200 - mean * mean);
  CHECK(std::fabs(mean) < 0.01);  // mm: the detection lag cancels against the zero
  CHECK(sd > 0.001 && sd < 0.02);
  CHECK(exact < 100);
}

TEST(RigMeasurement, PressStiffnessIsTheContactSlopeWithinTheSensorsNoise) {
  ps::JammingActuator actuator(1.0f, ps::Effects{});
  actuator.Reset();
  actuator.Step(20000, -60000);
  ps::RigMeasurement rig(5);
  for (int k = 0; k < 10; ++k) {
    const float k_measured = rig.Stiffness(actuator);
    DOUBLES_EQUAL(actuator.stiffness(), k_measured, 0.02 * actuator.stiffness());
    CHECK(k_measured != actuator.stiffness());
  }
  ps::RigMeasurement ideal(5, true);
  DOUBLES_EQUAL(actuator.stiffness(), ideal.Stiffness(actuator), 1e-3);
}
