// Level 1 of the plant: an electro-pneumatic regulator (static errors, minimum set pressure,
// dead time, its own pilot response) driving the flow into a line: tube and chamber, flow-limited
// by its valves (line_flow.h). Freestanding: the Cortex-M image links it.
#pragma once

#include <cstdint>

#include "palpa/hal/sim/line_flow.h"
#include "palpa/protocol/enums.h"

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
  float sign = 1;  ///< +1 pressure regulator, −1 vacuum regulator
  float full_scale_pa = 100000;
  float min_set_pa = 1000;   ///< below it the regulator vents to 0
  float lag_tau_s = 0.020f;  ///< the pilot stage: the regulator's own response, nothing behind it
  float dead_time_s = 0.005f;
  bool dynamics = true;  ///< false: level 0, the output is the command at once
  RegulatorErrors errors{};
  LineFlowSetup flow{};  ///< valves, tube and chamber behind the outlet
};

/// Factors on the line's assumed [A] numbers, for sweeping them (1: the plant's own).
struct FlowAssumptions {
  float flow = 1;     ///< every valve's full flow
  float band = 1;     ///< the main valve's proportional band
  float tube = 1;     ///< the tube's length (its volume and resistance)
  float chamber = 1;  ///< the chamber's volume
};

/// The regulator and line as plant_params.json gives them, without static errors: what a line of
/// this kind feeds on the thesis's actuators (a pressure line a pneumatic finger's cavity, a bias
/// line a jamming finger's air cushion, a vacuum line its granules).
RegulatorSetup NominalRegulatorSetup(protocol::LineKind kind, FlowAssumptions assumptions = {});

class RegulatorLine {
 public:
  RegulatorLine() = default;
  RegulatorLine(const RegulatorSetup& setup, float step_s);

  /// Advances one step with the nominal command pressure (what the DAC code asks for). With
  /// `vented` (supply shut off, dump valve open: the safe state in hardware) the line empties
  /// through the dump valve whatever the command; with `dump_open` alone (the board venting the
  /// line) the regulator follows its command and the dump valve passes air toward atmosphere too.
  void Step(float command_pa, bool vented = false, bool dump_open = false);

  float outlet_pa() const { return outlet_; }    ///< at the regulator outlet (sensor location)
  float chamber_pa() const { return chamber_; }  ///< in the actuator: the true pressure
  /// The pilot stage's pressure: where the regulator is taking its outlet.
  float pilot_pa() const { return pilot_; }

  /// The regulator's static output for a steady command (after its play settles).
  float StaticOutput(float command_magnitude_pa) const;

  /// Fault injection: a leak from the chamber to atmosphere, its conductance `ratio` times the
  /// tube's. The regulator supplies what leaks, so its outlet droops by its band × that flow /
  /// its full flow, and the chamber sits below the outlet by the tube's drop.
  void set_leak(float ratio) { flow_.set_leak(ratio); }

 private:
  RegulatorSetup setup_{};
  float lag_alpha_ = 1;
  uint8_t delay_steps_ = 0;
  float delay_[kMaxRegulatorDelaySteps] = {};
  uint8_t delay_index_ = 0;
  float play_ = 0;
  float pilot_ = 0;
  float outlet_ = 0;
  float chamber_ = 0;
  LineFlow flow_;
};

}  // namespace palpa::sim
