// The pressure loop's robustness: the template's trim keeps phase ≥ 45° and gain ≥ 6 dB over the
// chamber lags and dead times a line may have; the linear margins agree with the real StepLine in
// the time domain (an unstable case oscillates, bounded by the trim's authority); the trim's
// integrator dead band stops hunting against a valve dead band.
#include <initializer_list>

#include "pressure_loop.h"

#include "CppUTest/TestHarness.h"

namespace pt = palpa::testing;

TEST_GROUP(PressureLoop){};

TEST(PressureLoop, TheTemplateTrimHasMarginOverEveryChamberAndDeadTime) {
  for (float chamber : {0.05f, 0.15f, 0.3f, 0.7f}) {
    for (float dead : {0.002f, 0.005f, 0.01f, 0.02f}) {
      pt::LoopCase c;
      c.chamber_tau_s = chamber;
      c.dead_time_s = dead;
      const pt::Margins m = pt::LoopMargins(c);
      CHECK(m.phase_deg >= 45);
      CHECK(m.gain_db >= 6);
      CHECK(m.crossover_hz <= 1.0);  // DESIGN §4: crossover ≤ 1 Hz
      CHECK(pt::SettledRipple(c, 20) < 0.0005);
    }
  }
}

TEST(PressureLoop, LinearMarginsAndTheTimeDomainAgree) {
  pt::LoopCase unstable;
  unstable.gain = 64;  // far beyond what configuration accepts (kp ≤ 1, ki ≤ 2π/s)
  unstable.chamber_tau_s = 0.05f;
  unstable.dead_time_s = 0.02f;
  CHECK_FALSE(pt::LoopMargins(unstable).stable());
  const double ripple = pt::SettledRipple(unstable, 20);
  CHECK(ripple > 0.005);  // a sustained oscillation...
  CHECK(ripple < 0.11);   // ...bounded by the trim's ±5 % authority around the feed-forward
  pt::LoopCase stable = unstable;
  stable.gain = 16;
  CHECK(pt::LoopMargins(stable).stable());
  CHECK(pt::SettledRipple(stable, 20) < 0.0005);
}

TEST(PressureLoop, TheIntegratorDeadBandStopsHuntingAgainstAValveDeadBand) {
  pt::LoopCase c;
  c.gain = 6;  // near the largest ki configuration accepts
  c.chamber_tau_s = 0.7f;
  c.valve_dead_band = 0.005f;
  c.trim_dead_band = 0;
  CHECK(pt::SettledRipple(c, 60) > 0.0005);  // without it: a limit cycle
  c.trim_dead_band = 0.001f;                 // the template's ±0.1 % F.S.
  CHECK(pt::SettledRipple(c, 60) < 0.0001);
}
