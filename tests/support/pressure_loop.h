// The pressure loop of one line for robustness analysis: the firmware's own line pipeline (PI
// trim) against a regulator with dead time, lag and a valve dead band, feeding a chamber whose
// pressure the sensor reads (the slow case: the sensor behind the chamber's lag). Linear margins
// from the loop's frequency response, and a time-domain run of the real StepLine to confirm them.
#pragma once

namespace palpa::testing {

struct LoopCase {
  float gain = 1;              ///< multiplies the configured trim kp and ki
  float kp = 0.1f, ki = 1.0f;  ///< the pressure-line template's trim (ki per second)
  float regulator_tau_s = 0.02f;
  float dead_time_s = 0.005f;
  float chamber_tau_s = 0.15f;
  float valve_dead_band = 0.0f;   ///< fraction of full scale the regulator ignores (backlash)
  float trim_dead_band = 0.001f;  ///< fraction of full scale: the trim's integrator dead band
};

struct Margins {
  double phase_deg = 0;  ///< at the gain crossover; 180 when |L| never reaches 1
  double gain_db = 0;    ///< at the phase crossover; large when the phase never reaches -180°
  double crossover_hz = 0;
  bool stable() const { return phase_deg > 0 && gain_db > 0; }
};

/// Margins of L(z) = C(z) P(z) at the 1 kHz tick (dead time and one tick of compute delay in P).
Margins LoopMargins(const LoopCase& c);

/// Runs StepLine against the plant for `seconds` after a step to 50 % of full scale; returns the
/// peak-to-peak of the sensed pressure over the last 5 s as a fraction of full scale (a settled
/// loop gives about the dead band or less; hunting or instability gives more).
double SettledRipple(const LoopCase& c, int seconds);

}  // namespace palpa::testing
