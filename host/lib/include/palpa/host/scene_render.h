// The rendering rule of a scene: what each finger touches (and, where the tissue has depth, how
// deep the input's force presses) mapped to that finger's target in its own unit, within the range
// its curve covers, as requests Device::Set takes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_fingers.h"
#include "palpa/host/scene_input.h"
#include "palpa/host/scene_tissue.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::host {

/// The thesis's fingertip-stress line for the pneumatic actuator (§4.2 FE): stress ≈
/// 0.1748 · pressure + 5.91 kPa.
inline constexpr double kStressPerKpa = 0.1748;
inline constexpr double kStressAtZeroKpa = 5.91;

/// How a pneumatic finger renders stiffness (a jamming finger always renders N/mm).
enum class PneumaticMapping {
  kDeformation,      ///< u → deformation_mm range, through the finger's curve
  kLevel,            ///< u → the nearest of the level table's levels (the thesis's study levels)
  kFingertipStress,  ///< u → stress_kpa range → pressure by the stress line → deformation
};

struct RenderRule {
  /// The stiffness rendered softest (u = 0) and stiffest (u = 1), in the map's unit (N/mm of
  /// slope where the tissue has depth); lo == hi (the default, 0) takes the tissue's own range.
  double value_lo = 0, value_hi = 0;
  /// u = ((value − lo) / (hi − lo))^contrast, clamped to 0 … 1: above 1 stretches the stiff end
  /// (the thesis exaggerated contrast with a non-linear map), 1 is linear.
  double contrast = 1;
  /// Below this input force nothing touches: every finger is released (0.05 N: above the
  /// thesis's surface-following noise, 0.041 N at most).
  double contact_force_n = 0.05;
  PneumaticMapping pneumatic = PneumaticMapping::kDeformation;
  /// kDeformation: the deformation range (mm); hi ≤ 0 takes the finger's curve's maximum.
  double deformation_lo_mm = 0, deformation_hi_mm = 0;
  /// kFingertipStress: the stress range (kPa); the default spans the thesis's 0 … 30 kPa levels.
  double stress_lo_kpa = kStressAtZeroKpa;
  double stress_hi_kpa = kStressPerKpa * 30 + kStressAtZeroKpa;
};

/// Whether a rule can be rendered: a rising value range (or none), contrast in (0, 10], a contact
/// force of 0 … 100 N, rising deformation and stress ranges within the stress line's 0 … 100 kPa.
/// The reason starts "rule: ".
Outcome CheckRule(const RenderRule& rule);

/// One board finger a scene's finger drives, and what the library knows of it.
struct RenderFinger {
  uint8_t board_finger = 0;
  protocol::FingerSummary summary;
  FingerCurves curves;
};

/// What one finger got from one input sample.
struct FingerRender {
  ContactSample contact;
  bool touching = false;  ///< force at least the contact force, and the disc on the tissue
  double value = 0;       ///< the stiffness rendered: the map's, or the slope at the depth
  double depth_mm = 0;    ///< where the tissue has depth: how deep the force presses
  double u = 0;           ///< 0 … 1 after the range and contrast
  Request request;        ///< what Device::Set is asked
  Mapped mapped;          ///< the target the board is sent, within the finger's range
};

class SceneRenderer {
 public:
  /// Checks the tissue, the layout, the rule and that there is one finger per place in the
  /// layout (each a different board finger); the reason names what is wrong.
  static Result<SceneRenderer> Make(TissueMap tissue, FingerLayout layout, RenderRule rule,
                                    std::vector<RenderFinger> fingers,
                                    LevelTables levels = LevelTables::Shipped());

  /// Each finger's render for one input sample, in the layout's order. Deterministic.
  std::vector<FingerRender> Render(const SceneInput& input) const;
  /// Each finger's render from a value per finger already known (a tactile array's group means,
  /// in the layout's order), mapped over lo … hi with the rule's contrast and target mapping;
  /// no values (nullptr: the stream stopped) releases every finger — they go soft.
  std::vector<FingerRender> RenderValues(const std::vector<double>* values, double lo,
                                         double hi) const;
  /// What finger k (in the layout's order) is asked at u = 0 … 1, in its unit (mm or N/mm),
  /// within its curve: the ends of what the scene renders on it.
  double OutputAt(size_t k, double u) const;
  /// The requests for Device::Set (one per finger, all in one call: one stream frame).
  std::vector<FingerRequest> Requests(const std::vector<FingerRender>& renders) const;

  const TissueMap& tissue() const { return tissue_; }
  const FingerLayout& layout() const { return layout_; }
  const RenderRule& rule() const { return rule_; }
  const std::vector<RenderFinger>& fingers() const { return fingers_; }
  /// The stiffness range mapped to u = 0 … 1 (the rule's, or the tissue's own).
  double value_lo() const { return lo_; }
  double value_hi() const { return hi_; }

  SceneRenderer() = default;  // for Result<SceneRenderer>; Make is the way to get a usable one

 private:
  Request Target(const RenderFinger& f, double u) const;
  /// r.value over lo … hi to u, then the finger's target (r.touching), or released.
  void Map(FingerRender& r, const RenderFinger& f, double lo, double hi) const;

  TissueMap tissue_;
  FingerLayout layout_;
  RenderRule rule_;
  std::vector<RenderFinger> fingers_;
  LevelTables levels_;
  double lo_ = 0, hi_ = 0;
};

/// Where force `force_n` presses on a force-against-depth curve (the origin, then `force_n` at
/// each layer's depth): the first crossing, by linear interpolation, and the slope (N/mm) of the
/// segment it lies on; beyond the deepest layer, that layer's depth and the last slope.
struct DepthAtForce {
  double depth_mm = 0;
  double slope_n_per_mm = 0;
  bool beyond = false;  ///< the force is more than the deepest layer met
};
DepthAtForce PressDepth(const std::vector<ForceLayer>& layers, const std::vector<double>& force_n,
                        double force);

}  // namespace palpa::host
