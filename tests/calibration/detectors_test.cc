// Every failure detector on one short calibration with its fault injected and one clean, both
// in-process on free-running virtual time: the injected one fires and says what it measured, the
// clean one passes every check. The benchmark runs the same cases across many seeds. A zero that
// walks past the contact threshold stops the run, named as what it is.
#include <sys/stat.h>

#include <string>

#include "calibration_experiments.h"
#include "palpa/calibration/session.h"
#include "temp_dir.h"

// Last: its memory-leak macros redefine new.
#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
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

// The steepest drift the benchmark draws (6 mN a minute) walks the zero past the 10 mN contact
// threshold before the chamber step: the run stops there naming the sensor's zero, not the stage
// its surface search would have climbed to, and reports force_zero failing; only the journal is
// written, and a run resumed with the sensor settled takes the zero again and finishes.
TEST(Detectors, AZeroWalkedPastTheContactThresholdStopsTheRunNamingIt) {
  const std::string dir = pt::MakeTempDir("palpa-zero");
  cal::SessionOptions options;
  options.finger = pt::kJammingFinger;
  options.protocol = pt::ShortAdaptiveProtocol();
  options.out_dir = dir;
  options.date = "2026-11-22T12:00:00Z";
  {
    pt::SimRig sim({"thesis-5finger", pt::kJammingFinger, 6, 1005, {}});
    sim.force_drift_n_per_s = 0.006 / 60;
    cal::Session session(sim.rig(), "JAM-1", 1, true, options);
    CHECK(session.OpenOutput().ok());
    const palpa::host::Outcome o = session.Run(nullptr);
    CHECK(session.stopped());
    LONGS_EQUAL_TEXT((int)palpa::protocol::Status::kUnavailable, (int)o.status, o.message.c_str());
    STRCMP_CONTAINS("force_zero: the force sensor's zero has walked", o.message.c_str());
    STRCMP_CONTAINS("at or over the contact threshold of 10 mN, before the chamber step response",
                    o.message.c_str());
    const std::vector<palpa::host::QualityCheck>& checks = session.result().file.quality.checks;
    LONGS_EQUAL(1, checks.size());
    STRCMP_EQUAL("force_zero", checks[0].name.c_str());
    CHECK(!checks[0].passed);
    CHECK_TEXT(checks[0].value >= 10, checks[0].detail.c_str());  // mN, the stop's reading
  }
  struct stat st;
  CHECK(stat((dir + "/JAM-1.json").c_str(), &st) != 0);  // no calibration file
  const auto journal = cal::LoadJournal(dir + "/JAM-1.journal.json");
  CHECK_TEXT(journal.ok(), journal.message.c_str());
  CHECK(journal.value.contains("sweep") && !journal.value.contains("chamber"));
  pt::SimRig settled({"thesis-5finger", pt::kJammingFinger, 6, 1006, {}});
  options.resume = true;
  cal::Session resumed(settled.rig(), "JAM-1", 1, true, options);
  const palpa::host::Outcome o = resumed.Calibrate(nullptr);
  CHECK_TEXT(o.ok(), o.message.c_str());
  CHECK(stat((dir + "/JAM-1.json").c_str(), &st) == 0);
}
