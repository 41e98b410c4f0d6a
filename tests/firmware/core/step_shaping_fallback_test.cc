// Shaped steps where the model is wrong or the air cannot follow: fast target streams against a
// misidentified chamber stay bounded and stable, the fallback to unshaped steps (the supervisor's
// monitors through shaped steps, at the board's own windows:
// tests/firmware/boards/sim/shaped_step_monitors_test.cc), and the vents toward atmosphere.
#include <algorithm>
#include <cmath>

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

TEST_GROUP(StepShapingFallback){};

TEST(StepShapingFallback, FastTargetStreamsStayBoundedAgainstAMisidentifiedChamber) {
  for (float truth : {0.5f, 2.0f}) {  // the real chamber's lag × the model's
    LineUnderTest line(ShapedLine(20000, 30000), 0);
    auto& [p, s, out] = line;
    Air air(10, 0.02f * truth, 150.0f);  // twice the modelled dead time, a flow limit
    // A square wave faster than the chamber follows, then one it can follow: the overshoot of
    // each period of the slow wave does not grow, and every command stays within its bounds.
    float overshoot[6] = {};
    for (int k = 0; k < 12000; ++k) {
      const bool fast = k < 6000;
      const int period = fast ? 30 : 1000;
      const float target = (k / (period / 2)) % 2 == 0 ? 60000.0f : 20000.0f;
      const float command = Run(p, s, target, air.outlet, out);
      CHECK(command >= 0 && command <= 90000.0f + 1e-3f);
      CHECK(std::fabs(s.integrator_pa) <= 5000.0f + 1e-3f);
      air.Step(command);
      if (!fast && target > 50000) {
        float& o = overshoot[(k - 6000) / 1000];
        o = std::max(o, air.chamber - 60000);
      }
    }
    // (It changes from period to period only as the trim learns between steps: by less each time.)
    for (int i = 3; i < 6; ++i) {
      CHECK(overshoot[i] - overshoot[i - 1] <= 0.6f * (overshoot[i - 1] - overshoot[i - 2]) + 50);
    }
    CHECK(overshoot[5] < 2000);
    // Held at one target at the end, the chamber settles: no limit cycle.
    float low = 1e9f, high = -1e9f;
    for (int k = 0; k < 3000; ++k) {
      air.Step(Run(p, s, 40000, air.outlet, out));
      if (k > 2000) {
        low = std::min(low, air.outlet);
        high = std::max(high, air.outlet);
      }
    }
    CHECK(high - low < 200);
    DOUBLES_EQUAL(40000, air.chamber, 500);
  }
}

TEST(StepShapingFallback, AnAirPathFasterThanItsModelFallsBackToUnshapedSteps) {
  // The air path's regulator lags 20 ms; the models say 40 ms (misidentified × 2), or 20 ms.
  for (const uint32_t model_tau_us : {40000u, 20000u}) {
    pp::ConfigureLine c = ShapedLine(5000, 20000);
    c.model_tau_us = model_tau_us;
    LineUnderTest line(c, 10000);
    auto& [p, s, out] = line;
    Air air(5, 0.005f);
    air.pilot = air.outlet = air.chamber = 10000;
    const bool wrong = model_tau_us != 20000;
    for (int i = 0; i < 8; ++i) {
      const float from = i % 2 == 0 ? 10000.0f : 40000.0f, to = i % 2 == 0 ? 40000.0f : 10000.0f;
      float overshoot = 0;
      bool shaped = false;
      for (int k = 0; k < 600; ++k) {
        air.Step(Run(p, s, to, air.outlet, out));
        shaped = shaped || (out.status & ls::kShaping) != 0;
        overshoot = std::max(overshoot, (air.chamber - to) * (to > from ? 1.0f : -1.0f));
      }
      // A model twice too slow: the first step overshoots and says so; from then on the steps
      // are unshaped, without the overdrive, and land without overshoot. The right model shapes
      // every step and never falls back.
      CHECK_EQUAL(wrong && i > 0, !shaped);
      CHECK_EQUAL(wrong, s.shaping_fell_back);
      if (wrong && i == 0) CHECK_TEXT(overshoot > 2000, std::to_string(overshoot).c_str());
      if (i > 0) CHECK_TEXT(overshoot < 500, std::to_string(overshoot).c_str());
    }
  }
  // Configured again (a new chamber model): shaping gets its chance again.
  pc::LineState s;
  s.shaping_fell_back = true;
  pc::ResetLineState(pc::MakeLineParams(ShapedLine(), 1000), s, 0);
  CHECK(s.shaping_fell_back);  // a reset alone (the safe state) keeps it
}

TEST(StepShapingFallback, AnOutletStillShortOfAnEarlierTargetIsNoOvershoot) {
  // A vacuum line near the pump's pressure: the flow into the pump falls with the outlet's
  // absolute pressure, so a second after a step to −99 kPa the outlet has crept only to −94.
  // A small step back toward atmosphere (−98.5 kPa) then finds it on the step's far side of the
  // new target, beyond the target and the reference by more than kShapeFallbackPa, and the
  // overdrive's push carries it 0.3 kPa further. It was beyond before the overdrive began: it
  // lags the earlier step, slow air, and the line keeps shaping. An outlet that crosses the
  // target during the step still falls back (AnAirPathFasterThanItsModelFallsBackToUnshapedSteps).
  pp::ConfigureLine c = ShapedLine(200000, 20000);
  c.kind = pp::LineKind::kVacuum;
  c.command_max_pa = c.limit_min_pa = -100000;
  c.limit_max_pa = 0;
  LineUnderTest line(c, -60000);
  auto& [p, s, out] = line;
  float outlet = -60000;
  for (int k = 0; k < 2000; ++k) {
    Run(p, s, -99000, outlet, out);
    outlet = std::max(outlet - 25.0f, -94000.0f);
  }
  bool shaped = false;
  for (int k = 0; k < 1000; ++k) {
    Run(p, s, -98500, outlet, out);
    const bool shaping = (out.status & ls::kShaping) != 0;
    shaped = shaped || shaping;
    if (shaped && !shaping) outlet = -93700;  // the overdrive's push, after it
  }
  CHECK(shaped);
  CHECK_FALSE(s.shaping_fell_back);
}

TEST(StepShapingFallback, AShapedLineVentsBelowTheRegulatorsMinimumWhereItsLimitsHoldAtmosphere) {
  auto vents_at = [](const pp::ConfigureLine& c, float from, float to) {
    LineUnderTest line(c, from);
    auto& [p, s, out] = line;
    uint32_t vents = 0;
    pc::StepLine(p, s, to, pc::LineReading{true, 0, from}, out, &vents);
    return vents;
  };
  pp::ConfigureLine c = ShapedLine();
  c.line = 2;
  LONGS_EQUAL(1u << 2, vents_at(c, 30000, 0));
  LONGS_EQUAL(1u << 2, vents_at(c, 30000, 500));  // below the regulator's 1 kPa: commanded 0
  LONGS_EQUAL(0, vents_at(c, 30000, 10000));
  LONGS_EQUAL(0, vents_at(c, 0, 1000));
  pp::ConfigureLine plain = ShapedLine(20000, 0);  // not shaped: never
  plain.line = 2;
  LONGS_EQUAL(0, vents_at(plain, 30000, 0));
  pp::ConfigureLine above = c;  // limits that leave atmosphere out: never
  above.limit_min_pa = 2000;
  LONGS_EQUAL(0, vents_at(above, 30000, 0));
  const pp::ConfigureLine vacuum = VacuumLine();  // toward atmosphere from below
  LONGS_EQUAL(1u << 5, vents_at(vacuum, -30000, 0));
  LONGS_EQUAL(0, vents_at(vacuum, 0, -30000));
}

TEST(StepShapingFallback, AVacuumStepHeldAtAtmospheresLimitVentsAndItsModelFollowsTheOutlet) {
  // A vacuum line's step back toward atmosphere whose overdrive meets the line's upper limit
  // (0 kPa): its dump valve opens with the regulator's exhaust, and the regulator model starts
  // from the outlet the sensor reads (the exhaust's band slows it there, not the model's lag). A
  // pressure line whose overdrive meets its lower limit at 0 kPa does neither.
  struct Tick {
    uint32_t vents;
    float regulator;
    uint8_t status;
  };
  auto first_tick = [](const pp::ConfigureLine& c, float from, float to, float outlet) {
    LineUnderTest line(c, from);
    auto& [p, s, out] = line;
    uint32_t vents = 0;
    pc::StepLine(p, s, to, pc::LineReading{true, 0, outlet}, out, &vents);
    return Tick{vents, s.regulator_pa, out.status};
  };
  const pp::ConfigureLine vacuum = VacuumLine();
  const float alpha = 1.0f / 21.0f;  // 1 ms over the model's 20 ms lag + 1 ms
  const Tick up = first_tick(vacuum, -30000, -5000, -26000);
  CHECK((up.status & ls::kSaturated) != 0);
  LONGS_EQUAL(1u << 5, up.vents);
  DOUBLES_EQUAL(-26000 * (1 - alpha), up.regulator, 1);  // from the outlet, not from −30 kPa
  const Tick down = first_tick(vacuum, -5000, -30000, -5000);  // toward the pump: neither
  LONGS_EQUAL(0, down.vents);
  const Tick within = first_tick(vacuum, -50000, -40000, -48000);  // not held at 0 kPa: neither
  CHECK_FALSE((within.status & ls::kSaturated) != 0);
  LONGS_EQUAL(0, within.vents);
  pp::ConfigureLine pressure = ShapedLine();
  pressure.line = 2;
  const Tick falling = first_tick(pressure, 30000, 5000, 26000);
  CHECK((falling.status & ls::kSaturated) != 0);
  LONGS_EQUAL(0, falling.vents);
  DOUBLES_EQUAL(30000 * (1 - alpha), falling.regulator, 1);
}

TEST(StepShapingFallback, AFallenBackLineSlewsAgain) {
  // A shaped line runs without slew (the calibration sets it to 0); fallen back, its steps are
  // unshaped and slewed again: at the default's 200 kPa/s, or at the line's own where it has one.
  for (const uint32_t own : {0u, 100000u}) {
    pp::ConfigureLine c = ShapedLine(5000, 20000);
    c.slew_pa_per_s = own;
    LineUnderTest line(c, 10000);
    auto& [p, s, out] = line;
    Run(p, s, 40000, 10000, out);
    DOUBLES_EQUAL(own == 0 ? 40000 : 10100, s.slewed_pa, 1e-3);
    // Falling back on a step's overshoot: after the overdrive, the outlet runs beyond the target
    // and the model.
    pc::ResetLineState(p, s, 10000);
    float outlet = 30000;
    for (int k = 0; k < 400 && !s.shaping_fell_back; ++k) {
      Run(p, s, 40000, outlet, out);
      if ((out.status & ls::kShaping) == 0) outlet = 45000;
    }
    CHECK(s.shaping_fell_back);
    const float before = s.slewed_pa;
    Run(p, s, before - 30000, before, out);
    DOUBLES_EQUAL(before - (own == 0 ? 200 : 100), s.slewed_pa, 1e-2);
    CHECK(out.status & ls::kSlewing);
    pc::ResetLineState(p, s, 10000);  // the safe state keeps the fallback, and its slew
    Run(p, s, 40000, 10000, out);
    DOUBLES_EQUAL(10000 + (own == 0 ? 200 : 100), s.slewed_pa, 1e-2);
  }
}
