// Level 1's air path behind a regulator: its valves, its outlet volume (where the sensors sit),
// the tube and the chamber, with flow limited by the valves and the tube. Freestanding.
#pragma once

#include <cstdint>

namespace palpa::sim {

/// One line's pneumatics. Flows are ANR volume flows (m³/s of air at atmospheric pressure);
/// conductances follow ISO 6358 for valves (q = C · p_upstream · φ(p_down / p_up)) and
/// Hagen–Poiseuille for the tube (q = g · (p₁² − p₂²) / (2 p_atm), laminar, compressible).
struct LineFlowSetup {
  float sign = 1;                   ///< +1 pressure regulator, −1 vacuum regulator
  float atmosphere_pa = 101325;     ///< absolute; everything outside this file is gauge
  float supply_abs_pa = 301325;     ///< pressure class: the supply; vacuum class: the pump
  float main_conductance = 0;       ///< C of the main valve, m³/(s·Pa)
  float exhaust_conductance = 0;    ///< outlet ↔ atmosphere through the regulator, m³/(s·Pa)
  float critical_ratio = 0.4f;      ///< ISO 6358 b
  float band_pa = 10000;            ///< pilot − outlet that opens the main valve fully
  float outlet_volume_m3 = 3e-6f;   ///< regulator outlet + the tube's near half
  float chamber_volume_m3 = 3e-6f;  ///< chamber + the tube's far half
  float tube_conductance = 0;  ///< π r⁴ / (8 μ L), m³/(s·Pa); 0: outlet and chamber are one
  float dump_conductance = 0;  ///< the safe state's dump valve on the outlet, m³/(s·Pa)
};

class LineFlow {
 public:
  LineFlow() = default;
  LineFlow(const LineFlowSetup& setup, float step_s);

  /// One step with the regulator's pilot (its inner loop's pressure, gauge Pa): the main valve
  /// opens in proportion to pilot − outlet, fully beyond the band. `vented`: supply shut off and
  /// the dump valve open, whatever the pilot. `dump_open`: the dump valve open alone (the board
  /// vents the line toward atmosphere), the regulator still working.
  void Step(float pilot_pa, bool vented, bool dump_open = false);
  /// One step with the main valve held at `opening` (−1 … 1: exhaust/release … full flow).
  void StepOpen(float opening);
  /// Both volumes at `pa` (gauge), at rest.
  void Preset(float pa);

  float outlet_pa() const { return outlet_ - setup_.atmosphere_pa; }
  float chamber_pa() const { return chamber_ - setup_.atmosphere_pa; }
  /// Net flow the regulator passed into the line in the last step (ANR m³/s).
  float regulator_flow() const { return regulator_flow_; }
  const LineFlowSetup& setup() const { return setup_; }

  /// Fault injection: a leak from the chamber to atmosphere, laminar, its conductance `ratio`
  /// times the tube's (or the dump valve's where the line has no tube).
  void set_leak(float ratio) { leak_ = ratio < 0 ? 0 : ratio; }

 private:
  float Opening(float pilot_pa) const;
  void Advance(float opening, bool dump_open);
  float ValveFlow(float opening) const;

  LineFlowSetup setup_{};
  float sub_step_s_ = 0;
  uint8_t sub_steps_ = 1;
  float outlet_ = 101325;  // absolute Pa
  float chamber_ = 101325;
  float leak_ = 0;
  float regulator_flow_ = 0;
};

/// ISO 6358 flow function φ(r), r = p_down / p_up ≤ 1: 1 while choked (r ≤ b), an elliptic fall
/// to 0 at r = 1, made linear over the last 0.5 % so that an explicit step stays stable there.
float OrificeFlowFactor(float ratio, float critical_ratio);

}  // namespace palpa::sim
