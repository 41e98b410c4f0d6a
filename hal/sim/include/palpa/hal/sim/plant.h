// The simulated plant behind a board: one regulator and chamber per line, one actuator per
// finger, sensors; the level of detail chosen per use. Truth leaves it only through Truth().
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "palpa/hal/sim/actuators.h"
#include "palpa/hal/sim/regulator_line.h"
#include "palpa/hal/sim/sensors.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::sim {

/// Levels are cumulative: 0 ideal; 1 regulator dynamics, static errors, minimum set pressure,
/// flow into tube and chamber; 2 actuator hysteresis (and creep/rate when enabled); 3 real sensors
/// and rig.
struct PlantOptions {
  int level = 3;
  uint32_t unit = 0;          ///< actuator unit: 0 nominal, others drawn with the thesis's spread
  uint32_t seed = 1;          ///< regulator and sensor units, noise
  bool static_errors = true;  ///< regulator static errors (level ≥ 1)
  Effects effects{};
  /// Sweeps of the air path's assumed numbers and of the regulators' dead time (evaluations of
  /// how control copes with a plant unlike the nominal one); the defaults are the frozen plant.
  FlowAssumptions flow{};
  float dead_time_scale = 1;
};

struct LineTruth {
  float command_pa = 0;  ///< nominal pressure the DAC code asks for
  float outlet_pa = 0;   ///< at the regulator outlet, where the sensor sits
  float chamber_pa = 0;  ///< in the actuator: the true pressure
};

struct FingerTruth {
  bool jamming = false;
  float deformation_mm = 0;
  float stiffness_n_per_mm = 0;
};

struct PlantTruth {
  double time_s = 0;
  std::vector<LineTruth> lines;
  std::vector<FingerTruth> fingers;
};

class Plant {
 public:
  static constexpr float kStepS = 0.001f;

  /// The plant wired as the configuration says: regulator class, DAC scaling and sensor range
  /// per line; actuator kind per finger.
  Plant(const protocol::ConfigureLine* lines, uint8_t line_count,
        const protocol::ConfigureFinger* fingers, uint8_t finger_count, PlantOptions options);

  /// A DAC code arrives (from the board's analogue output).
  void SetDacCounts(uint8_t line, uint32_t counts);
  /// ADC counts of the line's pressure sensor now.
  uint32_t SensorCounts(uint8_t line) const;
  /// Advances the physics by one step (1 ms).
  void Step();
  /// The safe state in hardware: supply shut off and dump valve open vent every line.
  void SetVented(bool vented) { vented_ = vented; }
  bool vented() const { return vented_; }
  /// The lines' own dump valves (bit i: line i's open, the rest held shut), as the board's line
  /// vent outputs drive them; every one opens with the safe state's vent above.
  void SetLineVents(uint32_t open) { line_vents_ = open; }
  uint32_t line_vents() const { return line_vents_; }

  PlantTruth Truth() const;
  const PlantOptions& options() const { return options_; }
  uint8_t line_count() const { return static_cast<uint8_t>(lines_.size()); }
  /// The regulator of a line, for tests of level 1.
  const RegulatorLine& regulator(uint8_t line) const { return lines_[line].regulator; }
  JammingActuator* jamming(uint8_t finger);
  /// Fault injection: a leaking line (see RegulatorLine::set_leak).
  void SetLeak(uint8_t line, float ratio) { lines_[line].regulator.set_leak(ratio); }
  PneumaticActuator* pneumatic(uint8_t finger);

 private:
  struct Line {
    protocol::ConfigureLine config;
    RegulatorLine regulator;
    std::unique_ptr<PressureSensor> sensor;
    float command_pa = 0;
    uint32_t counts = 0;
  };
  struct Finger {
    protocol::ConfigureFinger config;
    std::unique_ptr<PneumaticActuator> pneumatic;
    std::unique_ptr<JammingActuator> jamming;
  };
  float NominalCommand(const protocol::ConfigureLine& c, uint32_t counts) const;

  PlantOptions options_;
  std::vector<Line> lines_;
  std::vector<Finger> fingers_;
  double time_s_ = 0;
  bool vented_ = true;       // valves unpowered until the board holds them
  uint32_t line_vents_ = 0;  // none released until a board drives them
};

}  // namespace palpa::sim
