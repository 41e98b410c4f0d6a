// Shaped steps in the line pipeline: off until the chamber model is known, beyond the target only
// as far as the bounds allow, a bumpless handover, the reference following what was commanded and
// the trim held through the step (fast streams, the fallback and the vents:
// step_shaping_fallback_test.cc).
#include <algorithm>
#include <cmath>
#include <random>

#include "CppUTest/TestHarness.h"
#include "step_shaping_support.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;
namespace ls = pp::line_status;
using step_shaping::Air;
using step_shaping::LineUnderTest;
using step_shaping::Run;
using step_shaping::ShapedLine;
using step_shaping::VacuumLine;

TEST_GROUP(StepShaping){};

TEST(StepShaping, OffUntilTheChamberModelIsKnownAndAnOverdriveAllowed) {
  for (const auto& c : {ShapedLine(0, 30000), ShapedLine(20000, 0)}) {
    LineUnderTest line(c, 10000);
    auto& [p, s, out] = line;
    CHECK_FALSE(p.shaping);
    DOUBLES_EQUAL(30000, Run(p, s, 30000, 10000, out), 1e-3);
    CHECK_FALSE(out.status & ls::kShaping);
  }
}

TEST(StepShaping, DrivesBeyondTheTargetThenHandsOverWithoutABump) {
  // The models are the air path's: the regulator's 20 ms lag, then a chamber that lags 5 ms more
  // (a pneumatic cavity: the regulator is led straight to the target) or 80 ms more (granules'
  // air: the regulator is led beyond it while the chamber is short).
  for (const float chamber_s : {0.005f, 0.08f}) {
    LineUnderTest line(ShapedLine(static_cast<uint32_t>(chamber_s * 1e6f)), 10000);
    auto& [p, s, out] = line;
    CHECK(p.shaping);
    Air shaped(0, chamber_s), plain(0, chamber_s);
    for (Air* a : {&shaped, &plain}) a->pilot = a->outlet = a->chamber = 10000;
    // The first tick goes to the bound: the target plus the overdrive.
    DOUBLES_EQUAL(60000, Run(p, s, 30000, 10000, out), 1e-3);
    CHECK(out.status & ls::kShaping);
    float previous = out.command_pa;
    int handover = -1, shaped_at = -1, plain_at = -1;
    float highest = 0;
    for (int k = 0; k < 1000; ++k) {
      const float command = k == 0 ? previous : Run(p, s, 30000, shaped.outlet, out);
      // Never below the target, then exactly the target for good.
      CHECK(command >= 30000 - 1e-3f);
      if (handover < 0 && command == 30000.0f) handover = k;
      if (handover >= 0) DOUBLES_EQUAL(30000, command, 1e-3);
      previous = command;
      shaped.Step(command);
      plain.Step(30000);
      highest = std::max(highest, shaped.chamber);
      if (shaped_at < 0 && std::fabs(shaped.chamber - 30000) < 400) shaped_at = k;
      if (plain_at < 0 && std::fabs(plain.chamber - 30000) < 400) plain_at = k;
    }
    CHECK(handover > 0 && handover < 500);
    CHECK((out.status & ls::kShaping) == 0);
    // Against an air path like the models: there in a third of the time, and no further than the
    // handover's dead band.
    CHECK_TEXT(shaped_at < plain_at / 3, std::to_string(shaped_at).c_str());
    CHECK_TEXT(highest < 30000 + 150, std::to_string(highest).c_str());
  }
}

TEST(StepShaping, AStepThatComesBackFromBeyondUsesTheCorrectionsOtherBranch) {
  // The regulator's play: approached from below it makes 1 kPa less than from above. A shaped
  // rising step comes back to its target from above, so it lands on the falling branch. The
  // sensor reads what the reference says, the trim off.
  pp::ConfigureLine c = ShapedLine();
  c.trim_kp = c.trim_ki_per_s = 0;
  c.correction_count = 2;
  c.correction[0] = {0, -1000, 0};
  c.correction[1] = {100000, 99000, 100000};
  for (const bool shaped : {false, true}) {
    c.overdrive_pa = shaped ? 30000 : 0;
    LineUnderTest line(c, 10000);
    auto& [p, s, out] = line;
    for (int k = 0; k < 500; ++k)
      pc::StepLine(p, s, 30000, pc::LineReading{true, 0, s.reference_pa}, out);
    DOUBLES_EQUAL(shaped ? 30000 : 31000, out.command_pa, 1);
  }
}

TEST(StepShaping, NeverBeyondTheOverdriveBoundOrTheLineLimitsAndSaysSo) {
  pp::ConfigureLine c = ShapedLine(40000, 20000);
  c.limit_max_pa = 45000;
  LineUnderTest line(c, 0);
  auto& [p, s, out] = line;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> target(0, 60000);
  bool saturated = false;
  for (int k = 0; k < 20000; ++k) {
    const float t = k % 37 == 0 ? target(rng) : s.slewed_pa;
    const float command = Run(p, s, t, 0, out);
    const float goal = std::min(t, 45000.0f);
    CHECK(command <= 45000.0f + 1e-3f);
    CHECK(command >= 0.0f);
    // The overdrive's bound, and the trim's authority on top of it.
    CHECK(command <= goal + 25000 + 1e-3f && command >= goal - 25000 - 1e-3f);
    saturated = saturated || (out.status & ls::kSaturated) != 0;
  }
  CHECK(saturated);  // some overdrive met the 45 kPa limit
}

TEST(StepShaping, TheReferenceFollowsWhatWasCommanded) {
  const pc::LineParams shaped = pc::MakeLineParams(ShapedLine(), 1000);
  const pc::LineParams plain = pc::MakeLineParams(ShapedLine(0), 1000);
  pc::LineState a, b;
  pc::ResetLineState(shaped, a, 10000);
  pc::ResetLineState(plain, b, 10000);
  pc::LineOutput out;
  for (int k = 0; k < 15; ++k) {
    Run(shaped, a, 30000, 10000, out);
    Run(plain, b, 30000, 10000, out);
  }
  // The regulator model saw the overdrive: ahead of where the target alone would have taken it.
  CHECK(a.reference_pa > b.reference_pa + 3000);
}

TEST(StepShaping, TheTrimHoldsThroughTheStepAndResumesAfter) {
  pp::ConfigureLine c = ShapedLine();
  c.limit_max_pa = 45000;  // the overdrive meets the limit, and the final clamp with it
  LineUnderTest line(c, 10000);
  auto& [p, s, out] = line;
  s.integrator_pa = 1200;  // what the trim had learnt of the regulator's static error
  // The outlet lags far behind an overdriven reference, then the step is held. Until the hold
  // ends the integrator keeps what it learnt; the final clamp does not unwind it either.
  // The step is under way until the line has a setpoint again (the overdrive, then the hold).
  int k = 0;
  for (; s.steady_pa != 30000.0f; ++k) {
    Run(p, s, 30000, 10000, out);
    DOUBLES_EQUAL(1200, s.integrator_pa, 1e-3);
  }
  CHECK(k >= p.shape_hold_ticks);
  for (int j = 0; j < 10; ++j) Run(p, s, 30000, 10000, out);
  CHECK(s.integrator_pa > 1200);  // the trim integrates a real shortfall again
}
