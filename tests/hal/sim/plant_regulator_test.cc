// The plant's regulators and air paths against their specification: level 0, then level 1.
#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/fastest_step.h"
#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/plant_params.h"
#include "plant_test_support.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
namespace pp = palpa::protocol;
namespace params = palpa::sim::params;
using palpa::sim::testing::Hold;
using palpa::sim::testing::MakePlant;

TEST_GROUP(PlantLevel0){};

TEST(PlantLevel0, OutputIsTheCommandAtOnce) {
  ps::Plant plant = MakePlant(0);
  Hold(plant, 0, 50000, 1);
  DOUBLES_EQUAL(50000, plant.Truth().lines[0].chamber_pa, 15);
}

TEST_GROUP(PlantLevel1){};

TEST(PlantLevel1, RegulatorAloneReaches90PercentInAbout50msAfterItsDeadTime) {
  // Nothing behind the outlet but the regulator's own passage: its pilot stage's response.
  ps::RegulatorSetup alone = ps::NominalRegulatorSetup(pp::LineKind::kPressure);
  alone.flow.tube_conductance = 0;
  alone.flow.chamber_volume_m3 = 0;
  ps::RegulatorLine line(alone, 0.001f);
  int first_move = -1, ninety = -1;
  for (int ms = 1; ms <= 300; ++ms) {
    line.Step(50000);
    const float out = line.outlet_pa();
    if (first_move < 0 && out > 1) first_move = ms;
    if (ninety < 0 && out >= 0.9f * 50000) ninety = ms;
  }
  CHECK(first_move >= 5 && first_move <= 7);
  CHECK_TEXT(ninety >= 45 && ninety <= 60, std::to_string(ninety).c_str());
}

TEST(PlantLevel1, AnOverdrivenRegulatorFillsNoFasterThanItsFullFlow) {
  // Full scale commanded on every line: the chamber's pressure rises no faster than the main
  // valve's full flow into the line's whole volume allows, and does reach that rate.
  for (pp::LineKind kind : {pp::LineKind::kPressure, pp::LineKind::kBias}) {
    const ps::RegulatorSetup setup = ps::NominalRegulatorSetup(kind);
    const ps::LineFlowSetup& f = setup.flow;
    const float full_flow = f.main_conductance * f.supply_abs_pa;  // choked, outlet at atmosphere
    const float bound = f.atmosphere_pa * full_flow / (f.outlet_volume_m3 + f.chamber_volume_m3);
    ps::RegulatorLine line(setup, 0.001f);
    float fastest = 0, before = 0;
    for (int ms = 0; ms < 300; ++ms) {
      line.Step(100000);
      fastest = std::max(fastest, (line.chamber_pa() - before) / 0.001f);
      before = line.chamber_pa();
    }
    CHECK_TEXT(fastest <= 1.05f * bound,
               (std::to_string(fastest) + " > " + std::to_string(bound)).c_str());
    CHECK(fastest >= 0.5f * bound);
  }
}

TEST(PlantLevel1, NoCommandBeatsTheFastestStep) {
  // The fastest step is a bound: the regulator commanded straight to the target, or over-driven
  // to its full scale until the chamber gets there, reaches it no sooner.
  struct Case {
    pp::LineKind kind;
    float from, to;
  };
  for (const Case& c :
       {Case{pp::LineKind::kPressure, 0, 10000}, Case{pp::LineKind::kPressure, 30000, 10000},
        Case{pp::LineKind::kPressure, 0, 80000}, Case{pp::LineKind::kVacuum, -10000, -100000},
        Case{pp::LineKind::kVacuum, -100000, 0}}) {
    const ps::RegulatorSetup setup = ps::NominalRegulatorSetup(c.kind);
    const ps::FastestStepResult best = ps::FastestStep(setup, c.from, c.to);
    CHECK(best.reach_s > setup.dead_time_s);
    const float band = 0.02f * std::fabs(c.to - c.from);
    for (bool overdrive : {false, true}) {
      ps::RegulatorLine line(setup, 0.001f);
      for (int ms = 0; ms < 20000; ++ms) line.Step(c.from);
      const float push = c.to > c.from ? 100000.0f : (c.to < c.from ? -100000.0f : 0.0f);
      const float extreme =
          setup.sign > 0 ? (push > 0 ? 100000.0f : 0.0f) : (push < 0 ? -100000.0f : 0.0f);
      int reach = -1;
      bool pushing = overdrive;
      for (int ms = 1; ms <= 30000 && reach < 0; ++ms) {
        // Over-driven until the chamber gets to the target (or past it), then the target.
        if ((c.to - line.chamber_pa()) * (c.to - c.from) <= 0) pushing = false;
        line.Step(pushing ? extreme : c.to);
        if (std::fabs(line.chamber_pa() - c.to) <= band) reach = ms;
      }
      CHECK(reach > 0);
      CHECK_TEXT(reach >= 1000 * best.reach_s - 1.0f,
                 (std::to_string(reach) + " ms < " + std::to_string(best.reach_s)).c_str());
    }
  }
}

TEST(PlantLevel1, TheNarrowVacuumTubeHoldsTheChamberBackNearFullVacuum) {
  // The regulator's outlet (where the sensor sits) gets to within 2 kPa of −100 kPa long before
  // the granules' air has gone through 1.2 mm of bore: the chamber's last few kPa take seconds.
  ps::Plant plant = MakePlant(1, 0, 1, false);
  Hold(plant, 5, 10000, 3000);
  int outlet_at = -1, chamber_at = -1;
  for (int ms = 1; ms <= 6000; ++ms) {
    Hold(plant, 5, 100000, 1);
    const auto t = plant.Truth().lines[5];
    if (outlet_at < 0 && t.outlet_pa <= -98000) outlet_at = ms;
    if (chamber_at < 0 && t.chamber_pa <= -98000) chamber_at = ms;
  }
  CHECK(outlet_at > 0 && outlet_at < chamber_at / 2);
  CHECK_TEXT(chamber_at > 1500, std::to_string(chamber_at).c_str());
}

TEST(PlantLevel1, FlowAssumptionsMoveTheFastestStepAsFlowWould) {
  // 0 → 80 kPa is flow-limited: twice the valve's flow nearly halves it, half the flow nearly
  // doubles it; the tube's length matters little on the 4 mm line, a lot on the vacuum's.
  auto reach = [](pp::LineKind kind, float from, float to, ps::FlowAssumptions a) {
    return ps::FastestStep(ps::NominalRegulatorSetup(kind, a), from, to).reach_s;
  };
  const float nominal = reach(pp::LineKind::kPressure, 0, 80000, {});
  const float fast = reach(pp::LineKind::kPressure, 0, 80000, {2, 1, 1, 1});
  const float slow = reach(pp::LineKind::kPressure, 0, 80000, {0.5f, 1, 1, 1});
  const float dead = params::kRegulatorDeadTimeS;
  DOUBLES_EQUAL(0.5, (fast - dead) / (nominal - dead), 0.1);
  DOUBLES_EQUAL(2.0, (slow - dead) / (nominal - dead), 0.3);
  const float vacuum = reach(pp::LineKind::kVacuum, -10000, -100000, {});
  const float long_tube = reach(pp::LineKind::kVacuum, -10000, -100000, {1, 1, 2, 1});
  CHECK(long_tube > 1.5f * vacuum);
}

TEST(PlantLevel1, ALeakDroopsTheOutletByTheFlowItTakes) {
  // The regulator supplies what leaks; its proportional main stage droops by band × flow / full
  // flow, and the chamber sits further below, across the tube.
  ps::RegulatorSetup setup = ps::NominalRegulatorSetup(pp::LineKind::kVacuum);
  ps::RegulatorLine line(setup, 0.001f);
  line.set_leak(0.1f);
  for (int ms = 0; ms < 20000; ++ms) line.Step(-60000);
  const float droop = line.outlet_pa() + 60000;
  CHECK(droop > 500);
  CHECK(line.chamber_pa() > line.outlet_pa() + 2000);
}

TEST(PlantLevel1, StaticErrorsStayWithinTheRegulatorSpecification) {
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    ps::Plant plant = MakePlant(1, 0, seed, true);
    for (float pa : {10000.0f, 50000.0f, 90000.0f}) {
      Hold(plant, 0, pa, 3000);
      const float error = plant.regulator(0).outlet_pa() - pa;
      // gain ±1 % + offset ±0.3 % F.S. + linearity ±1 % F.S. + the play (≤ 0.35 % F.S.) + 1 LSB
      CHECK(std::fabs(error) <= 0.01f * pa + 300 + 1000 + 350 + 25);
    }
  }
}

TEST(PlantLevel1, FeedForwardAloneShowsAboutOneKilopascalOfError) {
  double worst = 0;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    ps::Plant plant = MakePlant(1, 0, seed, true);
    Hold(plant, 0, 50000, 3000);
    worst = std::max(worst, std::fabs(static_cast<double>(plant.regulator(0).outlet_pa()) - 50000));
  }
  CHECK(worst > 700 && worst < 2700);
}

TEST(PlantLevel1, HysteresisAndSensitivityMakeRisingAndFallingDiffer) {
  ps::Plant plant = MakePlant(1, 0, 3, true);
  Hold(plant, 0, 50000, 3000);
  const float rising = plant.regulator(0).outlet_pa();
  Hold(plant, 0, 90000, 3000);
  Hold(plant, 0, 50000, 3000);
  const float falling = plant.regulator(0).outlet_pa();
  const float width = (params::kRegulatorHysteresisFs + params::kRegulatorSensitivityFs) * 100000;
  DOUBLES_EQUAL(width, falling - rising, 60);
}

TEST(PlantLevel1, BelowTheMinimumSetPressureTheRegulatorVents) {
  ps::Plant plant = MakePlant(1, 0, 1, false);
  Hold(plant, 0, 800, 500);
  DOUBLES_EQUAL(0, plant.regulator(0).outlet_pa(), 1);
  Hold(plant, 0, 2000, 500);
  CHECK(plant.regulator(0).outlet_pa() > 1500);
}

TEST(PlantLevel1, VacuumRegulatorAndVenting) {
  ps::Plant plant = MakePlant(1, 0, 1, false);
  Hold(plant, 5, 60000, 3000);  // line 5 is a vacuum line: counts mean −60 kPa
  DOUBLES_EQUAL(-60000, plant.Truth().lines[5].chamber_pa, 200);
  plant.SetVented(true);
  for (int ms = 0; ms < 300; ++ms) plant.Step();
  CHECK(std::fabs(plant.Truth().lines[5].chamber_pa) < 0.05f * 100000);
}
