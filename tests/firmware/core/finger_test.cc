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

namespace {

/// One step into fresh line arrays (NaN where the finger wrote nothing).
struct FingerStep {
  float setpoints[pp::kMaxLines];
  uint8_t status[pp::kMaxLines];
  FingerStep(const pc::FingerParams& p, pc::FingerState& s, uint64_t now_us, float applied = 0) {
    for (float& v : setpoints) v = __builtin_nanf("");
    for (uint8_t& v : status) v = 0xFF;
    pc::StepFinger(p, s, applied, pc::FingerTick{now_us, 300000, setpoints, status});
  }
};

}  // namespace

TEST(Finger, HomesVentedThenFollows) {
  pc::FingerState s;
  s.target = 2000;
  FingerStep out(pneumatic, s, 1000);
  CHECK(s.phase != pc::HomePhase::kHomed);
  DOUBLES_EQUAL(0, out.setpoints[0], 0);
  LONGS_EQUAL(0, out.status[0]);
  CHECK(__builtin_isnan(out.setpoints[1]));  // nothing written on lines it does not own
  LONGS_EQUAL(0xFF, out.status[1]);
  FingerStep(pneumatic, s, 300999);
  CHECK(s.phase != pc::HomePhase::kHomed);
  FingerStep(pneumatic, s, 301000);  // dwell over: the last homing tick
  CHECK(s.phase == pc::HomePhase::kHomed);
  out = FingerStep(pneumatic, s, 302000);
  DOUBLES_EQUAL(48249, out.setpoints[0], 1);
  LONGS_EQUAL(0, out.status[0]);
  pc::RequireHoming(s);
  DOUBLES_EQUAL(0, FingerStep(pneumatic, s, 303000).setpoints[0], 0);
  CHECK(s.phase != pc::HomePhase::kHomed);
}

TEST(Finger, JammingHomesWithVacuumReleasedAndTheBiasOn) {
  pc::FingerState s;
  s.target = 1300;
  const uint8_t bias = jamming.line_a, vacuum = jamming.line_b;
  FingerStep out(jamming, s, 0);
  CHECK(s.phase != pc::HomePhase::kHomed);
  DOUBLES_EQUAL(20000, out.setpoints[bias], 0);
  DOUBLES_EQUAL(0, out.setpoints[vacuum], 0);
  FingerStep(jamming, s, 300000);
  out = FingerStep(jamming, s, 301000);
  DOUBLES_EQUAL(20000, out.setpoints[bias], 0);
  DOUBLES_EQUAL(-100000, out.setpoints[vacuum], 1);
  LONGS_EQUAL(0, out.status[vacuum]);
}
