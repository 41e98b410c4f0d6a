// Every failure detector on one short calibration with its fault injected and one clean, both
// in-process on free-running virtual time: the injected one fires and says what it measured, the
// clean one passes every check. The benchmark runs the same cases across many seeds.
#include <string>

#include "calibration_experiments.h"

#include "CppUTest/TestHarness.h"

namespace pt = palpa::testing;

namespace {

void Expect(pt::Detector d, const char* words) {
  const pt::DetectorCase bad = pt::RunDetectorCase(d, true, 3);
  CHECK_TEXT(bad.fired, (std::string(pt::DetectorName(d)) + " missed: " + bad.detail).c_str());
  CHECK_TEXT(bad.detail.find(words) != std::string::npos, bad.detail.c_str());
  const pt::DetectorCase clean = pt::RunDetectorCase(d, false, 3);
  CHECK_TEXT(clean.ran, clean.error.c_str());
  std::string flags;
  for (const std::string& f : clean.flags) flags += f + "; ";
  CHECK_TEXT(!clean.fired && !clean.any_other, flags.c_str());
}

}  // namespace

TEST_GROUP(Detectors){};

TEST(Detectors, TooFewPoints) { Expect(pt::Detector::kPoints, "map conditions"); }
TEST(Detectors, NoiseBeyondTheSensorsClass) { Expect(pt::Detector::kNoise, "the sensor's class"); }
TEST(Detectors, ADriftingForceZero) { Expect(pt::Detector::kForceZero, "from the tare"); }
TEST(Detectors, ALeakingChamber) { Expect(pt::Detector::kLeak, "kPa at a"); }
TEST(Detectors, AnActuatorThatChangedSinceItsLastCalibration) {
  Expect(pt::Detector::kPrevious, "differs from the calibration of");
}
