// The plant against the thesis numbers and the regulator's specification, level by level.
#include <algorithm>
#include <cmath>
#include <vector>

#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/fastest_step.h"
#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/plant_params.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
namespace pp = palpa::protocol;
namespace params = palpa::sim::params;

namespace {

ps::Plant MakePlant(int level, uint32_t unit = 0, uint32_t seed = 1, bool errors = true,
                    ps::Effects effects = {}) {
  const auto& c = *palpa::core::FindBoardConfig("thesis-5finger");
  ps::PlantOptions o;
  o.level = level;
  o.unit = unit;
  o.seed = seed;
  o.static_errors = errors;
  o.effects = effects;
  ps::Plant plant(c.lines.data(), c.line_count, c.fingers.data(), c.finger_count, o);
  plant.SetVented(false);
  return plant;
}

uint32_t CountsFor(float pa) { return static_cast<uint32_t>(pa / 100000.0f * 4095.0f + 0.5f); }

void Hold(ps::Plant& plant, uint8_t line, float pa, int ms) {
  plant.SetDacCounts(line, CountsFor(std::fabs(pa)));
  for (int i = 0; i < ms; ++i) plant.Step();
}

double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxy / sxx;
}

}  // namespace

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

TEST_GROUP(PneumaticLoop){};

TEST(PneumaticLoop, MajorLoopMatchesTable54WithinTolerance) {
  ps::Plant plant = MakePlant(2);
  std::vector<double> p, rising, falling;
  std::vector<double> p_down;
  for (int kpa = 0; kpa <= 100; kpa += 10) {
    Hold(plant, 0, static_cast<float>(kpa) * 1000, 2500);
    p.push_back(plant.Truth().lines[0].chamber_pa / 1000.0);  // the true pressure, as on the rig
    rising.push_back(plant.Truth().fingers[0].deformation_mm);
  }
  for (int kpa = 100; kpa >= 0; kpa -= 10) {
    Hold(plant, 0, static_cast<float>(kpa) * 1000, 2500);
    p_down.insert(p_down.begin(), plant.Truth().lines[0].chamber_pa / 1000.0);
    falling.insert(falling.begin(), plant.Truth().fingers[0].deformation_mm);
  }
  const double tol = params::kTolerancesSlopeTolerance;
  const double sr = Slope(p, rising), sf = Slope(p_down, falling);
  CHECK_TEXT(std::fabs(sr / params::kTolerancesRisingSlopeMmPerKpa - 1) <= tol,
             std::to_string(sr).c_str());
  CHECK_TEXT(std::fabs(sf / params::kTolerancesFallingSlopeMmPerKpa - 1) <= tol,
             std::to_string(sf).c_str());
  DOUBLES_EQUAL(params::kTolerancesGapAt10kpaMm, falling[1] - rising[1],
                params::kTolerancesGapAt10kpaToleranceMm);
  double mean_gap = 0;
  for (int i = 2; i <= 8; ++i) mean_gap += falling[i] - rising[i];
  DOUBLES_EQUAL(params::kTolerancesMeanGapMm, mean_gap / 7, params::kTolerancesMeanGapToleranceMm);
  // Each branch stays near its thesis line, not only its slope.
  double rms = 0;
  for (int i = 1; i <= 9; ++i) {
    const double dr = rising[i] - (0.0428 * p[i] - 0.3032),
                 df = falling[i] - (0.0475 * p_down[i] - 0.1333);
    rms += dr * dr + df * df;
  }
  CHECK(std::sqrt(rms / 18) <= params::kTolerancesBranchRmsToFitMm);
  // The loop closes at its turning points.
  DOUBLES_EQUAL(rising.back(), falling.back(), 0.02);
  DOUBLES_EQUAL(0, falling.front(), 0.02);
}

TEST(PneumaticLoop, DensityIsNotPrandtlIshlinskii) {
  // A PI model's minor loops of equal amplitude have equal widths wherever they sit; this film's
  // grow with the mean input.
  auto minor_width = [](float center_kpa) {
    ps::Plant plant = MakePlant(2, 0, 1, false);
    plant.SetVented(false);
    Hold(plant, 0, (center_kpa - 10) * 1000, 2000);
    Hold(plant, 0, (center_kpa + 10) * 1000, 2000);
    Hold(plant, 0, center_kpa * 1000, 2000);
    const float down = plant.Truth().fingers[0].deformation_mm;
    Hold(plant, 0, (center_kpa - 10) * 1000, 2000);
    Hold(plant, 0, center_kpa * 1000, 2000);
    return down - plant.Truth().fingers[0].deformation_mm;
  };
  const float low = minor_width(25), high = minor_width(75);
  CHECK(low > 0.01f);
  CHECK_TEXT(high > 1.2f * low, (std::to_string(low) + " vs " + std::to_string(high)).c_str());
}

TEST(PneumaticLoop, CreepKeepsMovingAfterAStep) {
  ps::Effects creep;
  creep.creep = true;
  ps::Plant plant = MakePlant(2, 0, 1, false, creep);
  Hold(plant, 0, 60000, 2000);
  const float early = plant.Truth().fingers[0].deformation_mm;
  Hold(plant, 0, 60000, 15000);
  const float late = plant.Truth().fingers[0].deformation_mm;
  CHECK(late > early * 1.005f);
  CHECK(late < early * (1 + 2 * params::kPneumaticCreepFraction));
}

TEST(PneumaticLoop, FastCyclesWidenTheLoop) {
  // Loop width at 30 kPa of chamber pressure, against the chamber pressure itself: with rate
  // dependence the film lags a fast input and the loop opens up.
  auto width_at_30 = [](bool rate) {
    ps::Effects e;
    e.rate = rate;
    ps::Plant plant = MakePlant(2, 0, 1, false, e);
    float up = -1, down = -1;
    for (int ms = 0; ms <= 4000; ++ms) {
      const float phase = static_cast<float>(ms) / 2000.0f;  // 0→60→0 kPa in 4 s
      plant.SetDacCounts(0, CountsFor(60000.0f * (phase <= 1 ? phase : 2 - phase)));
      plant.Step();
      const auto t = plant.Truth();
      if (up < 0 && ms < 2000 && t.lines[0].chamber_pa >= 30000) up = t.fingers[0].deformation_mm;
      if (down < 0 && ms > 2000 && t.lines[0].chamber_pa <= 30000)
        down = t.fingers[0].deformation_mm;
    }
    return down - up;
  };
  const float fast = width_at_30(true), slow = width_at_30(false);
  CHECK_TEXT(fast > slow + 0.05f, (std::to_string(fast) + " vs " + std::to_string(slow)).c_str());
}

TEST(PneumaticLoop, UnitsDifferWithTheThesisSpreadMostlyMidToHigh) {
  // Per measurement point (rising and falling, 10..90 kPa), the spread of the deformation over
  // units relative to its mean: the assumed unit spread on average, smaller low than high.
  constexpr int kUnits = 60;
  const std::vector<float> points{10, 20, 30, 40, 50, 60, 70, 80, 90};
  std::vector<std::vector<double>> at(2 * points.size());
  std::vector<double> slope_change;  // a unit's 80-kPa-to-20-kPa ratio, against the nominal's
  ps::Plant nominal = MakePlant(2, 0);
  for (int unit = 1; unit <= kUnits; ++unit) {
    ps::Plant plant = MakePlant(2, static_cast<uint32_t>(unit));
    const ps::PneumaticActuator& a = *plant.pneumatic(0);
    for (size_t i = 0; i < points.size(); ++i) {
      at[2 * i].push_back(a.RisingMajorMm(points[i]));
      at[2 * i + 1].push_back(a.FallingMajorMm(points[i]));
    }
    const ps::PneumaticActuator& n = *nominal.pneumatic(0);
    slope_change.push_back((a.RisingMajorMm(80) / n.RisingMajorMm(80)) /
                           (a.RisingMajorMm(20) / n.RisingMajorMm(20)));
  }
  auto spread = [](const std::vector<double>& v) {
    double sum = 0, sum2 = 0;
    for (double x : v) sum += x, sum2 += x * x;
    const double mean = sum / v.size();
    return std::sqrt(sum2 / v.size() - mean * mean) / mean;
  };
  double mean_spread = 0;
  for (const auto& v : at) mean_spread += spread(v) / at.size();
  DOUBLES_EQUAL(params::kPneumaticUnitSpread, mean_spread, 0.2 * params::kPneumaticUnitSpread);
  CHECK(spread(at[14]) > 1.3 * spread(at[2]));  // 80 kPa rising against 20 kPa rising
  // Not a gain: the units' deformation at 80 kPa against 20 kPa differs from unit to unit.
  CHECK(spread(slope_change) > 0.01);
}

TEST(PneumaticLoop, TheUnitSpreadFactorScalesHowUnitsDiffer) {
  // Halved and doubled (the sweep of the assumption), the units' differences follow.
  auto spread_at_60 = [](float factor) {
    ps::Effects e;
    e.unit_spread = factor;
    double sum = 0, sum2 = 0;
    constexpr int kUnits = 40;
    for (int unit = 1; unit <= kUnits; ++unit) {
      ps::Plant plant = MakePlant(2, static_cast<uint32_t>(unit), 1, true, e);
      const double x = plant.pneumatic(0)->RisingMajorMm(60);
      sum += x;
      sum2 += x * x;
    }
    const double mean = sum / kUnits;
    return std::sqrt(sum2 / kUnits - mean * mean) / mean;
  };
  const double nominal = spread_at_60(1);
  DOUBLES_EQUAL(0.5, spread_at_60(0.5f) / nominal, 0.05);
  DOUBLES_EQUAL(2.0, spread_at_60(2) / nominal, 0.2);
}

TEST_GROUP(JammingStiffness){};

TEST(JammingStiffness, EndPointsAndShapeFollowFig536) {
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  const float tol = params::kTolerancesStiffnessToleranceNPerMm;
  DOUBLES_EQUAL(0.7, j->StaticStiffness(20000, 0), tol);
  DOUBLES_EQUAL(1.3, j->StaticStiffness(20000, -100000), tol);
  float max_slope_bias = 0, max_slope_none = 0;
  for (int v = 0; v < 100; v += 5) {
    const float a = static_cast<float>(-v) * 1000, b = static_cast<float>(-v - 5) * 1000;
    max_slope_bias =
        std::max(max_slope_bias, j->StaticStiffness(20000, b) - j->StaticStiffness(20000, a));
    max_slope_none = std::max(max_slope_none, j->StaticStiffness(0, b) - j->StaticStiffness(0, a));
    CHECK(j->StaticStiffness(20000, b) >= j->StaticStiffness(20000, a));  // monotone
  }
  CHECK(max_slope_none > 2 * max_slope_bias);  // "more abrupt" without bias
}

TEST(JammingStiffness, AirAloneStiffensALittleAndTheCurvesAboveZeroAlmostOverlap) {
  // §5.4.3, Fig 5-36(a): without vacuum, air in the cushion raised the stiffness a little; the
  // curves for 5, 10 and 20 kPa almost overlapped.
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  const float none = j->StaticStiffness(0, 0);
  CHECK_TEXT(j->StaticStiffness(20000, 0) > 1.01f * none, std::to_string(none).c_str());
  CHECK(j->StaticStiffness(20000, 0) < 1.06f * none);  // "a little"
  for (float bias : {5000.0f, 10000.0f}) {
    CHECK(j->StaticStiffness(bias, 0) > 1.01f * none);
    CHECK(std::fabs(j->StaticStiffness(bias, 0) / j->StaticStiffness(20000, 0) - 1) < 0.015f);
  }
}

TEST(JammingStiffness, BiasWidensTheVacuumSpanWhileTheTopBarelyRises) {
  // §5.4.3, §5.5.2: with vacuum, the inflated cushion amplified the stiffness variation and spread
  // the vacuum levels' curves apart, while the maximum force barely rose.
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  auto span = [&](float bias) {
    return j->StaticStiffness(bias, -100000) - j->StaticStiffness(bias, 0);
  };
  CHECK_TEXT(span(20000) > 1.05f * span(0),
             (std::to_string(span(20000)) + " vs " + std::to_string(span(0))).c_str());
  CHECK(span(15000) > span(0) && span(15000) < span(20000));
  const float top = j->StaticStiffness(20000, -100000) / j->StaticStiffness(0, -100000);
  CHECK(top > 1.0f && top < 1.1f);
}

TEST(JammingStiffness, TheBiasAssumptionsSweepAsTheirFactorsSay) {
  auto at = [](float stiffening, float widening, float bias, float vacuum) {
    ps::Effects e;
    e.bias_stiffening = stiffening;
    e.bias_widening = widening;
    ps::Plant plant = MakePlant(2, 0, 1, false, e);
    return plant.jamming(3)->StaticStiffness(bias, vacuum);
  };
  // Anchored at 20 kPa bias: the axis range stays there whatever the factors.
  for (float f : {0.5f, 2.0f}) {
    DOUBLES_EQUAL(0.7, at(f, f, 20000, 0), 1e-4);
    DOUBLES_EQUAL(1.3, at(f, f, 20000, -100000), 1e-4);
  }
  const float rise_half = at(0.5f, 1, 20000, 0) / at(0.5f, 1, 0, 0) - 1;
  const float rise_double = at(2, 1, 20000, 0) / at(2, 1, 0, 0) - 1;
  DOUBLES_EQUAL(4.0, rise_double / rise_half, 0.2);
}

TEST(JammingStiffness, VacuumHistoryShowsWithinItsSweptSize) {
  for (float fraction : {0.05f, 0.1f, 0.2f}) {
    ps::Effects e;
    e.history = fraction;
    ps::Plant plant = MakePlant(2, 0, 1, false, e);
    ps::JammingActuator* j = plant.jamming(3);
    j->Step(20000, -50000);
    const float from_below = j->stiffness();
    j->Step(20000, -100000);
    j->Step(20000, -50000);
    const float from_above = j->stiffness();
    const float effect = (from_above - from_below) / 0.6f;
    CHECK(effect > 0.4f * fraction);
    CHECK(effect <= fraction * 1.001f);
  }
}

TEST(JammingStiffness, PressLoopsStayBelowTheLoadingWorkAndFollowVacuumAndBias) {
  ps::Plant plant = MakePlant(2);
  ps::JammingActuator* j = plant.jamming(3);
  auto loop = [&](float bias, float vacuum, float& work) {
    j->Step(bias, vacuum);
    double load = 0, unload = 0;
    const int n = 300;
    for (int i = 0; i < n; ++i) {
      const float d = 3.0f * (static_cast<float>(i) + 0.5f) / n;
      load += j->PressForce(d, 3.0f, true) * 3.0 / n;
      unload += j->PressForce(d, 3.0f, false) * 3.0 / n;
      CHECK(j->PressForce(d, 3.0f, false) >= 0);
    }
    work = static_cast<float>(load);
    return static_cast<float>(load - unload);
  };
  float w0 = 0, w1 = 0, w2 = 0, w3 = 0;
  const float at0 = loop(20000, 0, w0), at60 = loop(20000, -60000, w1),
              at100 = loop(20000, -100000, w2);
  const float unbiased100 = loop(0, -100000, w3);
  CHECK(at0 < w0 && at60 < w1 && at100 < w2 && unbiased100 < w3);
  CHECK(at100 / w2 > 1.3f * at60 / w1);                          // loops grow beyond −60 kPa
  DOUBLES_EQUAL(0.35, (at100 / w2) / (unbiased100 / w3), 0.02);  // bias shrinks them by 65 %
}

TEST_GROUP(PlantSensors){};

TEST(PlantSensors, IdealBelowLevelThreeAndWithinAccuracyAtIt) {
  ps::PressureSensor ideal(0, 103421, true, 1);
  DOUBLES_EQUAL(50000, ideal.PressureOf(ideal.Read(50000, 0.001f)), 8);
  for (uint32_t seed = 1; seed < 40; ++seed) {
    ps::PressureSensor real(0, 103421, false, seed);
    double sum = 0;
    for (int i = 0; i < 200; ++i) sum += real.PressureOf(real.Read(50000, 0.001f));
    DOUBLES_EQUAL(50000, sum / 200, 0.0025 * 103421 + 20);
  }
}

TEST(PlantSensors, ForceSensorResolution) {
  ps::ForceSensor f(true, 1);
  DOUBLES_EQUAL(1.002, f.Read(1.0031), 1e-6);
  ps::LinearStage stage;
  stage.MoveTo(3.0f, 0.1f);
  for (int i = 0; i < 10000; ++i) stage.Step(0.001f);
  DOUBLES_EQUAL(1.0, stage.position_mm(), 1e-4);
}

TEST(PlantSensors, SameSeedSameRun) {
  auto run = [](uint32_t seed) {
    ps::Plant plant = MakePlant(3, 2, seed);
    Hold(plant, 0, 30000, 500);
    return plant.SensorCounts(0) * 100000u + plant.SensorCounts(5);
  };
  LONGS_EQUAL(run(4), run(4));
  CHECK(run(4) != run(5));
}
