// The rig's measurements: close to the truth, never equal to it, with the errors the rig
// explains (the thesis's repeatability, contact-detection jitter, force noise in the press
// regression).
#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/plant_params.h"
#include "palpa/hal/sim/rig_measurement.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;

TEST_GROUP(RigMeasurement){};

TEST(RigMeasurement, DeformationRepeatsWithinTheThesisRepeatabilityAndNoBiasAfterZeroing) {
  // The same deformation read again and again: relative spread the thesis's 2.82 % per point
  // (five calliper readings), no bias (the detection lag cancels against the zero).
  ps::RigMeasurement rig(3);
  rig.Zero(0);
  constexpr int kReads = 600;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < kReads; ++k) {
    const double e = (rig.Deformation(2.0f) - 2.0) / 2.0;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / kReads, sd = std::sqrt(sum2 / kReads - mean * mean);
  CHECK(std::fabs(mean) < 0.004);
  DOUBLES_EQUAL(palpa::sim::params::kRigRepeatability, sd, 0.004);
  // Near zero deformation only the contact detection's jitter is left: a few micrometres.
  double small = 0;
  for (int k = 0; k < 100; ++k) small = std::max(small, std::fabs(rig.Deformation(0.0f) - 0.0));
  CHECK(small > 0 && small < 0.02);
  ps::RigMeasurement ideal(3, true);
  ideal.Zero(0);
  DOUBLES_EQUAL(2.0, ideal.Deformation(2.0f), 1e-6);
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
