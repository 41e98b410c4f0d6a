// Level 2 of the plant: what the fingers do with the pressure they get. Host only.
#pragma once

#include <cstdint>
#include <memory>

#include "palpa/hal/sim/preisach.h"

namespace palpa::sim {

/// Which second-order effects are on (palpa-sim --effects), and factors on assumed [A] numbers
/// for sweeping them (1: the plant's own).
struct Effects {
  bool creep = false;
  bool rate = false;
  float history = -1;  ///< jamming history effect as a fraction of the stiffness range; <0: default
  float bias_stiffening = 1;  ///< × the air cushion's own stiffening at no vacuum
  float bias_widening = 1;    ///< × how much the cushion widens the vacuum span
  float unit_spread = 1;      ///< × the assumed spread between actuator units
};

/// How one pneumatic unit differs from the nominal one (all 1 or 0 for the nominal unit). Units
/// differ mostly in the mid-to-high deflection range (thesis §5.5.1), so besides a plain gain the
/// loop grows differently with pressure and has its own width: no gain maps one onto another.
struct PneumaticUnit {
  float gain = 1;    ///< the whole deformation
  float growth = 0;  ///< extra loop density at the top of the range, fading to 0 at the bottom
  float width = 1;   ///< the loop's width (alpha − beta spread of its density)
};

/// Pneumatic fingertip: deformation (mm) of the film over the cavity against chamber pressure.
/// A non-Prandtl-Ishlinskii Preisach loop plus a reversible part, with creep and rate
/// dependence when enabled; one unit drawn with the thesis's spread.
class PneumaticActuator {
 public:
  PneumaticActuator(PneumaticUnit unit, Effects effects);
  void Reset();
  /// Advances by dt with the chamber pressure (Pa); returns the deformation in mm.
  float Step(float chamber_pa, float dt_s);
  float deformation_mm() const { return deformation_mm_; }
  /// The quasi-static major loop (no creep, no rate), for the Table 5-4 comparison.
  float RisingMajorMm(float kpa) const;
  float FallingMajorMm(float kpa) const;
  /// Fault injection: the unit changed since it was calibrated (worn, damaged, swapped).
  void ScaleUnit(float factor) { unit_gain_ *= factor; }

 private:
  float Reversible(float kpa) const;
  float unit_gain_;
  Effects effects_;
  std::shared_ptr<PreisachModel> loop_;
  float rate_kpa_ = 0;
  float creep_mm_ = 0;
  float deformation_mm_ = 0;
};

/// Pneumatic + granular-jamming finger: stiffness (N/mm) against vacuum and bias, with the
/// vacuum-history effect, and the force-depth loop of one press.
class JammingActuator {
 public:
  JammingActuator(float unit_gain, Effects effects);
  void Reset();
  /// Advances with the chamber pressures (bias Pa ≥ 0, vacuum Pa ≤ 0); returns N/mm.
  float Step(float bias_pa, float vacuum_pa);
  float stiffness() const { return stiffness_; }
  /// Stiffness without history, for a steady vacuum and bias. Anchored at the user study's
  /// 20 kPa bias; the air cushion stiffens a little by itself and widens the vacuum's span.
  float StaticStiffness(float bias_pa, float vacuum_pa) const;
  float history_fraction() const { return history_fraction_; }
  /// Fault injection: the unit changed since it was calibrated (worn, damaged, swapped).
  void ScaleUnit(float factor) { unit_gain_ *= factor; }

  /// Force (N) of a press at depth_mm, loading or unloading, to max_depth_mm, at the current
  /// vacuum and bias. The loop between the two is the material hysteresis (a): always smaller
  /// than the loading work.
  float PressForce(float depth_mm, float max_depth_mm, bool loading) const;
  float PressLoopFraction() const;

 private:
  float unit_gain_;
  Effects effects_;
  float history_fraction_;
  std::shared_ptr<PreisachModel> history_;
  float history_norm_ = 1;
  float bias_ = 0;
  float vacuum_ = 0;
  float stiffness_ = 0;
};

}  // namespace palpa::sim
