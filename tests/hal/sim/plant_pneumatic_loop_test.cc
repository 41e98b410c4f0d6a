// The pneumatic finger's stiffness loop against the thesis (table 5.4): hysteresis, creep, units.
#include <cmath>
#include <vector>

#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/plant_params.h"
#include "plant_test_support.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
namespace params = palpa::sim::params;
using palpa::sim::testing::CountsFor;
using palpa::sim::testing::Hold;
using palpa::sim::testing::MakePlant;
using palpa::sim::testing::Slope;

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
