// The supervisor's slow monitors through shaped steps, end to end at the board's own windows
// (thesis-5finger: implausible sensor over 3 s, leak after 5 s, 5 kPa tolerance): targets held
// longer than those windows after bursts of fast shaped steps, to and from atmosphere, latch
// nothing; the same steps on a leaking chamber latch the leak, so the monitors are not blinded by
// the shaping (and the quiet run could fail).
#include <memory>
#include <random>

#include "palpa/protocol/faults.h"
#include "raw_line_session.h"

#include "CppUTest/TestHarness.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;
namespace ps = palpa::sim;

namespace {

constexpr uint8_t kPneumaticLine = 0;

/// Line 0 shaped as the calibration leaves it (its chamber's lag, 20 kPa overdrive, no slew).
std::unique_ptr<pb::RawLineSession> ShapedSession() {
  ps::PlantOptions plant;
  plant.level = 3;
  return std::make_unique<pb::RawLineSession>(plant, [](pp::ConfigureLine& c) {
    c.slew_pa_per_s = 0;
    c.chamber_tau_us = 6000;
    c.overdrive_pa = 20000;
  });
}

/// Bursts of shaped steps 20–200 ms apart, each ending on a target held for 6 s (longer than
/// every slow monitor's window); returns the faults latched when the first one latched, or at
/// the end.
uint32_t BurstsAndHolds(pb::RawLineSession& s, int holds) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> kpa(0, 90), burst_ms(20, 200);
  for (int h = 0; h < holds; ++h) {
    for (int k = 0; k < 8; ++k) {
      s.Set({{kPneumaticLine, 1000 * kpa(rng)}});
      for (int ms = burst_ms(rng); ms > 0; --ms) s.Tick();
    }
    s.Set({{kPneumaticLine, h % 3 == 0 ? 0 : 1000 * (10 + kpa(rng) % 80)}});
    for (int ms = 0; ms < 6000; ++ms) {
      s.Tick();
      if (s.Faults() != 0) return s.Faults();
    }
  }
  return s.Faults();
}

}  // namespace

TEST_GROUP(ShapedStepMonitors){};

TEST(ShapedStepMonitors, QuietThroughShapedStepsHeldLongerThanTheirWindows) {
  auto s = ShapedSession();
  LONGS_EQUAL(0, BurstsAndHolds(*s, 6));
  CHECK_FALSE(s->ShapingFellBack(kPneumaticLine));
}

TEST(ShapedStepMonitors, ALeakingChamberIsStillCaughtThroughShapedSteps) {
  auto s = ShapedSession();
  s->plant().SetLeak(kPneumaticLine, 2.0f);
  const uint32_t faults = BurstsAndHolds(*s, 6);
  CHECK_TEXT(faults & (1u << static_cast<uint8_t>(pp::Fault::kLeak)),
             "a leaking shaped line went unnoticed");
}
