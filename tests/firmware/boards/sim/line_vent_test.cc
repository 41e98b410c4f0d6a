// Venting through a line's own dump valve, end to end on the level-3 plant: a shaped step toward
// atmosphere reaches it within the goal (the regulator alone cannot: its pilot stops at
// 0 kPa), never beyond it; the valve closes on the next step without a bump; a line that may not
// vent never does; every valve is open while the board is safe; the supervisor stays quiet
// through a fast stream of steps to and from atmosphere.
#include <algorithm>
#include <cmath>
#include <random>

#include "raw_line_session.h"
#include "steps_measure.h"

#include "CppUTest/TestHarness.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;
namespace ps = palpa::sim;

namespace {

constexpr uint8_t kPneumatic = 0, kBias = 3, kVacuum = 5;
constexpr uint32_t kAllVents = (1u << pp::kMaxLines) - 1u;

/// Lines 0, 3 and 5 with their chambers' lags known (those the calibration identifies on the
/// nominal unit) and a 20 kPa overdrive, as the calibration uploads them; `overdrive_pa` 0: not
/// shaped. `static_errors` false: regulators without the static error the calibration's
/// correction takes away (these lines have none uploaded).
std::unique_ptr<pb::RawLineSession> Session(int32_t overdrive_pa = 20000,
                                            bool static_errors = true) {
  ps::PlantOptions plant;
  plant.level = 3;
  plant.static_errors = static_errors;
  return std::make_unique<pb::RawLineSession>(plant, [overdrive_pa](pp::ConfigureLine& c) {
    c.slew_pa_per_s = 0;
    c.chamber_tau_us = c.line == kVacuum ? 47000 : 6000;
    c.overdrive_pa = overdrive_pa;
  });
}

void Dwell(pb::RawLineSession& s, int ms) {
  for (int i = 0; i < ms; ++i) s.Tick();
}

/// The goal for the transition: max(150 ms, 1.2 × the plant's fastest step).
double GoalMs(pp::LineKind kind, double from_pa, double to_pa) {
  const ps::FastestStepResult fastest = ps::FastestStep(
      ps::NominalRegulatorSetup(kind), static_cast<float>(from_pa), static_cast<float>(to_pa));
  return pb::GoalMs(1000.0 * fastest.settle_s);
}

}  // namespace

TEST_GROUP(LineVents){};

TEST(LineVents, EveryValveIsOpenWhileTheBoardIsSafe) {
  auto s = Session();
  Dwell(*s, 1);
  CHECK(s->Safe());  // no setpoints yet
  LONGS_EQUAL(kAllVents, s->Vents());
  LONGS_EQUAL(kAllVents, s->PlantVents());
  s->Set({{kPneumatic, 10000}});
  Dwell(*s, 3);
  CHECK_FALSE(s->Safe());
  CHECK_EQUAL(0u, s->PlantVents() & (1u << kPneumatic));
}

TEST(LineVents, AShapedStepToAtmosphereVentsAndSettlesWithinTheGoal) {
  auto s = Session();
  s->Set({{kPneumatic, 30000}});
  Dwell(*s, 1500);
  CHECK_EQUAL(0u, s->PlantVents() & (1u << kPneumatic));
  double lowest = 0;
  s->Set({{kPneumatic, 0}});
  Dwell(*s, 3);  // the setpoint's tick opens the valve, the plant's next millisecond has it
  CHECK(s->PlantVents() & (1u << kPneumatic));
  for (int ms = 0; ms < 1000; ++ms) {
    s->Tick();
    lowest = std::min(lowest, s->Chamber(kPneumatic));
  }
  DOUBLES_EQUAL(0, lowest, 1.0);  // atmosphere, never beyond it
  // Settling from the command, the whole step again (the valve stays open at 0 kPa).
  s->Set({{kPneumatic, 30000}});
  Dwell(*s, 1500);
  const pb::StepFigures f = pb::RunStep(*s, kPneumatic, 30000, 0, 1000);
  CHECK_TEXT(f.settle_ms <= GoalMs(pp::LineKind::kPressure, 30000, 0), "30 → 0 kPa too slow");
  LONGS_EQUAL(0, s->Faults());
}

TEST(LineVents, AVacuumStepToAtmosphereVentsAndSettlesWithinTheGoal) {
  auto s = Session();
  s->Set({{kBias, 20000}, {kVacuum, -30000}});
  Dwell(*s, 2000);
  const pb::StepFigures f = pb::RunStep(*s, kVacuum, -30000, 0, 1000);
  CHECK(s->PlantVents() & (1u << kVacuum));
  CHECK_EQUAL(0u, s->PlantVents() & (1u << kBias));  // the bias holds its 20 kPa
  CHECK_TEXT(f.settle_ms <= GoalMs(pp::LineKind::kVacuum, -30000, 0), "-30 → 0 kPa too slow");
  DOUBLES_EQUAL(0, f.overshoot_pa, 1.0);
  DOUBLES_EQUAL(20000, s->Chamber(kBias), 1000);
  LONGS_EQUAL(0, s->Faults());
}

TEST(LineVents, LeavingAtmosphereClosesTheValveWithoutABump) {
  auto s = Session(20000, false);
  s->Set({{kPneumatic, 0}});
  Dwell(*s, 500);
  CHECK(s->PlantVents() & (1u << kPneumatic));
  s->Set({{kPneumatic, 10000}});
  Dwell(*s, 3);
  CHECK_EQUAL(0u, s->PlantVents() & (1u << kPneumatic));
  s->Set({{kPneumatic, 0}});
  Dwell(*s, 500);
  const pb::StepFigures f = pb::RunStep(*s, kPneumatic, 0, 10000, 1000);
  CHECK_TEXT(f.settle_ms <= GoalMs(pp::LineKind::kPressure, 0, 10000), "0 → 10 kPa too slow");
  CHECK(f.overshoot_pa <= 500);
  CHECK_EQUAL(0, f.crossings);
}

TEST(LineVents, ALineThatMayNotVentNeverDoes) {
  auto s = Session(0);  // not shaped
  s->Set({{kPneumatic, 30000}});
  Dwell(*s, 1000);
  s->Set({{kPneumatic, 0}});
  for (int ms = 0; ms < 500; ++ms) {
    s->Tick();
    CHECK_EQUAL(0u, s->PlantVents() & (1u << kPneumatic));
  }
}

TEST(LineVents, TheSupervisorStaysQuietThroughAFastStreamToAndFromAtmosphere) {
  auto s = Session();
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> dwell(5, 400), pressure(1, 90), vacuum(1, 90);
  s->Set({{kBias, 20000}});
  Dwell(*s, 500);
  double lowest = 0, highest = -1e9;
  for (int step = 0; step < 120; ++step) {
    const bool atmosphere = step % 2 == 0;
    s->Set({{kPneumatic, atmosphere ? 0 : 1000 * pressure(rng)},
            {kVacuum, atmosphere ? 0 : -1000 * vacuum(rng)}});
    for (int ms = dwell(rng); ms > 0; --ms) {
      s->Tick();
      lowest = std::min(lowest, s->Chamber(kPneumatic));
      highest = std::max(highest, s->Chamber(kVacuum));
    }
  }
  Dwell(*s, 3000);  // the slow monitors' windows pass over the stream's end too
  LONGS_EQUAL(0, s->Faults());
  CHECK(lowest > -1000);  // the pneumatic chamber never below atmosphere
  CHECK(highest < 1000);  // the vacuum chamber never above it
}
