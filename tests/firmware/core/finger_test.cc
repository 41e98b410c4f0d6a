// Fingers: static inverse (target 0 → 0 Pa), homing before following, jamming bias.
#include "palpa/core/finger.h"
#include "palpa/core/board_configs.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

TEST_GROUP(Finger) {
  const pc::BoardConfig& config = *pc::FindBoardConfig("thesis-5finger");
  pc::FingerParams pneumatic = pc::MakeFingerParams(config.fingers[0], 100000);
  pc::FingerParams jamming = pc::MakeFingerParams(config.fingers[3], 100000);
};

TEST(Finger, StaticInverseFollowsTheThesisFitAndMapsZeroToZero) {
  DOUBLES_EQUAL(0, pc::StaticInverse(pneumatic, 0), 0);
  DOUBLES_EQUAL(26415, pc::StaticInverse(pneumatic, 1000), 1);
  // Between points: linear; Table 5-4's all-data fit gives (1.5 + 0.2098) / 0.0458 kPa.
  DOUBLES_EQUAL((1.5 + 0.2098) / 0.0458 * 1000, pc::StaticInverse(pneumatic, 1500), 5);
  DOUBLES_EQUAL(100000, pc::StaticInverse(pneumatic, 4370), 1);
  DOUBLES_EQUAL(-50000, pc::StaticInverse(jamming, 1000), 1);
  DOUBLES_EQUAL(0, pc::StaticInverse(jamming, 500), 0);  // below the stiffest-at-0-vacuum point
  LONGS_EQUAL(4370, pneumatic.max_target);
  CHECK(pc::UnitOf(pp::FingerKind::kJamming) == pp::OutputUnit::kStiffnessMilliNewtonPerMm);
}

TEST(Finger, HomesVentedThenFollows) {
  pc::FingerState s;
  s.target = 2000;
  auto out = pc::StepFinger(pneumatic, s, 1000, 300000, 0);
  CHECK(out.homing);
  DOUBLES_EQUAL(0, out.setpoint_a, 0);
  out = pc::StepFinger(pneumatic, s, 300999, 300000, 0);
  CHECK(out.homing);
  out = pc::StepFinger(pneumatic, s, 301000, 300000, 0);  // dwell over: the last homing tick
  out = pc::StepFinger(pneumatic, s, 302000, 300000, 0);
  CHECK_FALSE(out.homing);
  DOUBLES_EQUAL(48249, out.setpoint_a, 1);
  pc::RequireHoming(s);
  CHECK(pc::StepFinger(pneumatic, s, 303000, 300000, 0).homing);
}

TEST(Finger, JammingHomesWithVacuumReleasedAndTheBiasOn) {
  pc::FingerState s;
  s.target = 1300;
  auto out = pc::StepFinger(jamming, s, 0, 300000, 0);
  CHECK(out.homing);
  DOUBLES_EQUAL(20000, out.setpoint_a, 0);
  DOUBLES_EQUAL(0, out.setpoint_b, 0);
  pc::StepFinger(jamming, s, 300000, 300000, 0);
  out = pc::StepFinger(jamming, s, 301000, 300000, 0);
  DOUBLES_EQUAL(20000, out.setpoint_a, 0);
  DOUBLES_EQUAL(-100000, out.setpoint_b, 1);
}
