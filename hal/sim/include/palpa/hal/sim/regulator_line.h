// Level 1 of the plant: an electro-pneumatic regulator (static errors, minimum set pressure,
// dead time, lag) feeding a chamber through tubing. Freestanding: the Cortex-M image links it.
#pragma once

#include <cstdint>

namespace palpa::sim {

inline constexpr uint8_t kMaxRegulatorDelaySteps = 32;

/// One regulator unit's static errors (all zero for an ideal regulator).
struct RegulatorErrors {
  float gain = 0;  ///< relative, e.g. 0.01 = +1 %
  float offset_pa = 0;
  float linearity_pa = 0;  ///< amplitude of the bow, largest mid-scale
  float play_pa = 0;       ///< half-width of hysteresis + sensitivity (a backlash on the command)
};

struct RegulatorSetup {
  float sign = 1;  ///< +1 pressure regulator, -1 vacuum regulator
  float full_scale_pa = 100000;
  float min_set_pa = 1000;  ///< below it the regulator vents to 0
  float lag_tau_s = 0.020f;
  float dead_time_s = 0.005f;
  float chamber_tau_s = 0.15f;
  bool dynamics = true;  ///< false: level 0, the output is the command at once
  RegulatorErrors errors{};
};

class RegulatorLine {
 public:
  RegulatorLine() = default;
  RegulatorLine(const RegulatorSetup& setup, float step_s);

  /// Advances one step with the nominal command pressure (what the DAC code asks for). With
  /// `vented` (supply shut off, dump valve open: the safe state in hardware) the outlet and the
  /// chamber fall to 0 whatever the command.
  void Step(float command_pa, bool vented = false);

  float outlet_pa() const { return outlet_; }    ///< at the regulator outlet (sensor location)
  float chamber_pa() const { return chamber_; }  ///< in the actuator: the true pressure

  /// The regulator's static output for a steady command (after its play settles).
  float StaticOutput(float command_magnitude_pa) const;

  /// Fault injection: a leak from the chamber to atmosphere, its conductance `ratio` times the
  /// tubing's. The chamber then holds outlet / (1 + ratio), and the regulator's outlet droops by
  /// what flows (its flow is finite), so a leak shows at the sensor only through that droop.
  void set_leak(float ratio) { leak_ = ratio < 0 ? 0 : ratio; }

 private:
  RegulatorSetup setup_{};
  float lag_alpha_ = 1;
  float chamber_alpha_ = 1;
  float vent_alpha_ = 1;
  uint8_t delay_steps_ = 0;
  float delay_[kMaxRegulatorDelaySteps] = {};
  uint8_t delay_index_ = 0;
  float play_ = 0;
  float outlet_ = 0;
  float chamber_ = 0;
  float leak_ = 0;
};

}  // namespace palpa::sim
