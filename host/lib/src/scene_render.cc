// The rendering rule: contact, depth under the input's force, the stiffness range and contrast,
// and each finger kind's target through its curve, clamped to what the finger can render.
#include "palpa/host/scene_render.h"
#include "number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace palpa::host {
namespace {

/// The smallest and largest slope of force against depth anywhere on the tissue.
std::pair<double, double> SlopeRange(const TissueMap& t) {
  double lo = INFINITY, hi = -INFINITY;
  for (size_t k = 0; k < t.nx * t.ny; ++k) {
    double depth = 0, force = 0;
    for (const ForceLayer& l : t.layers) {
      const double slope = (l.force_n[k] - force) / (l.depth_mm - depth);
      lo = std::min(lo, slope);
      hi = std::max(hi, slope);
      depth = l.depth_mm;
      force = l.force_n[k];
    }
  }
  return {lo, hi};
}

}  // namespace

Outcome CheckRule(const RenderRule& r) {
  auto fail = [](const std::string& why) { return Outcome::Fail(Status::kInvalidArgument, why); };
  if (!std::isfinite(r.value_lo) || !std::isfinite(r.value_hi) || r.value_lo > r.value_hi) {
    return fail("rule: value_lo " + Num(r.value_lo) + " and value_hi " + Num(r.value_hi) +
                " are not a range (lo ≤ hi; equal takes the tissue's)");
  }
  if (!(r.contrast > 0 && r.contrast <= 10))
    return fail("rule: contrast " + Num(r.contrast) + " is not within (0, 10]");
  if (!(r.contact_force_n >= 0 && r.contact_force_n <= 100))
    return fail("rule: contact_force_n " + Num(r.contact_force_n) + " is not within 0 … 100 N");
  if (!(r.deformation_lo_mm >= 0 && std::isfinite(r.deformation_hi_mm) &&
        (r.deformation_hi_mm <= 0 || r.deformation_hi_mm > r.deformation_lo_mm))) {
    return fail("rule: deformation " + Num(r.deformation_lo_mm) + " … " + Num(r.deformation_hi_mm) +
                " mm is not a range (hi ≤ 0 takes the curve's)");
  }
  const double stress_max = kStressPerKpa * 100 + kStressAtZeroKpa;
  if (!(r.stress_lo_kpa >= kStressAtZeroKpa && r.stress_hi_kpa > r.stress_lo_kpa &&
        r.stress_hi_kpa <= stress_max)) {
    return fail("rule: stress " + Num(r.stress_lo_kpa) + " … " + Num(r.stress_hi_kpa) +
                " kPa is not a range within the stress line's " + Num(kStressAtZeroKpa) + " … " +
                Num(stress_max) + " kPa (0 … 100 kPa)");
  }
  return {};
}

DepthAtForce PressDepth(const std::vector<ForceLayer>& layers, const std::vector<double>& force_n,
                        double force) {
  DepthAtForce out;
  double depth = 0, met = 0;
  for (size_t l = 0; l < layers.size() && l < force_n.size(); ++l) {
    const double span = layers[l].depth_mm - depth;
    out.slope_n_per_mm = (force_n[l] - met) / span;
    if (force_n[l] >= force && force_n[l] > met) {
      out.depth_mm = depth + span * std::clamp((force - met) / (force_n[l] - met), 0.0, 1.0);
      return out;
    }
    depth = layers[l].depth_mm;
    met = force_n[l];
  }
  out.depth_mm = depth;
  out.beyond = true;
  return out;
}

Result<SceneRenderer> SceneRenderer::Make(TissueMap tissue, FingerLayout layout, RenderRule rule,
                                          std::vector<RenderFinger> fingers, LevelTables levels) {
  if (Outcome ok = CheckTissue(tissue); !ok.ok()) {
    ok.message = "tissue " + tissue.name + ": " + ok.message;
    return ok;
  }
  if (Outcome ok = CheckLayout(layout); !ok.ok()) {
    ok.message = "layout " + layout.name + ": " + ok.message;
    return ok;
  }
  if (Outcome ok = CheckRule(rule); !ok.ok()) return ok;
  if (fingers.size() != layout.fingers.size()) {
    return {Status::kInvalidArgument,
            "fingers: " + std::to_string(fingers.size()) + " board fingers for the " +
                std::to_string(layout.fingers.size()) + " places of layout " + layout.name};
  }
  std::set<uint8_t> used;
  for (size_t f = 0; f < fingers.size(); ++f) {
    if (!used.insert(fingers[f].board_finger).second) {
      return {Status::kInvalidArgument, "fingers[" + std::to_string(f) + "]: board finger " +
                                            std::to_string(fingers[f].board_finger) +
                                            " drives another place of the layout too"};
    }
  }
  if (rule.pneumatic == PneumaticMapping::kLevel && levels.pneumatic_kpa.empty())
    return {Status::kInvalidArgument, "rule: the level mapping needs a pneumatic level table"};
  SceneRenderer r;
  const auto [lo, hi] = tissue.has_depth() ? SlopeRange(tissue) : tissue.Range();
  r.lo_ = rule.value_lo < rule.value_hi ? rule.value_lo : lo;
  r.hi_ = rule.value_lo < rule.value_hi ? rule.value_hi : hi;
  r.tissue_ = std::move(tissue);
  r.layout_ = std::move(layout);
  r.rule_ = rule;
  r.fingers_ = std::move(fingers);
  r.levels_ = std::move(levels);
  return r;
}

Request SceneRenderer::Target(const RenderFinger& f, double u) const {
  const FingerCurves& c = f.curves;
  if (f.summary.kind == protocol::FingerKind::kJamming) {
    return {TargetKind::kStiffnessNPerMm,
            c.stiffness_at_0 + u * (c.stiffness_at_full_vacuum - c.stiffness_at_0)};
  }
  switch (rule_.pneumatic) {
    case PneumaticMapping::kLevel: {
      const double top = static_cast<double>(levels_.pneumatic_kpa.size() - 1);
      return {TargetKind::kLevel, std::round(u * top)};
    }
    case PneumaticMapping::kFingertipStress: {
      const double stress = rule_.stress_lo_kpa + u * (rule_.stress_hi_kpa - rule_.stress_lo_kpa);
      const double kpa = std::clamp((stress - kStressAtZeroKpa) / kStressPerKpa, 0.0, 100.0);
      return {TargetKind::kDeformationMm, DeformationAtPressure(c, kpa)};
    }
    case PneumaticMapping::kDeformation:
      break;
  }
  // A range wider than the finger's curve is held to the curve: the finger's limits bound it.
  const double hi = rule_.deformation_hi_mm > 0 ? rule_.deformation_hi_mm : c.max_deformation_mm;
  const double mm = rule_.deformation_lo_mm + u * (hi - rule_.deformation_lo_mm);
  return {TargetKind::kDeformationMm, std::clamp(mm, 0.0, c.max_deformation_mm)};
}

std::vector<FingerRender> SceneRenderer::Render(const SceneInput& in) const {
  const std::vector<ContactSample> contacts = SampleFingers(tissue_, layout_, in.x_mm, in.y_mm);
  std::vector<FingerRender> out(contacts.size());
  for (size_t k = 0; k < contacts.size(); ++k) {
    FingerRender& r = out[k];
    const RenderFinger& f = fingers_[k];
    r.contact = contacts[k];
    // A force that is not a number touches nothing: released is the safe default.
    r.touching = in.force_n >= rule_.contact_force_n && r.contact.coverage > 0;
    if (r.touching) {
      if (tissue_.has_depth()) {
        const DepthAtForce d = PressDepth(tissue_.layers, r.contact.force_n, in.force_n);
        r.value = d.slope_n_per_mm;
        r.depth_mm = d.depth_mm;
      } else {
        r.value = r.contact.value;
      }
    }
    Map(r, f, lo_, hi_);
  }
  return out;
}

void SceneRenderer::Map(FingerRender& r, const RenderFinger& f, double lo, double hi) const {
  r.request = {TargetKind::kNormalized, 0};  // released: 0 mm, or the vacuum off
  if (r.touching) {
    const double span = hi - lo;
    const double linear = span > 0 ? std::clamp((r.value - lo) / span, 0.0, 1.0) : 0.0;
    r.u = std::pow(linear, rule_.contrast);
    r.request = Target(f, r.u);
  }
  // Clamped, never refused: the rule's range may ask past what a finger's curve covers.
  r.mapped = MapRequest(f.summary, levels_, f.curves, r.request, RangePolicy::kClamp);
}

double SceneRenderer::OutputAt(size_t k, double u) const {
  const RenderFinger& f = fingers_.at(k);
  return MapRequest(f.summary, levels_, f.curves, Target(f, u), RangePolicy::kClamp).target /
         1000.0;
}

std::vector<FingerRender> SceneRenderer::RenderValues(const std::vector<double>* values, double lo,
                                                      double hi) const {
  std::vector<FingerRender> out(fingers_.size());
  for (size_t k = 0; k < out.size(); ++k) {
    FingerRender& r = out[k];
    // A value that is not a number touches nothing, as an input's force that is not one.
    r.touching = values != nullptr && k < values->size() && std::isfinite((*values)[k]);
    if (r.touching) r.value = (*values)[k];
    Map(r, fingers_[k], lo, hi);
  }
  return out;
}

std::vector<FingerRequest> SceneRenderer::Requests(const std::vector<FingerRender>& renders) const {
  std::vector<FingerRequest> out;
  for (size_t k = 0; k < renders.size() && k < fingers_.size(); ++k)
    out.push_back({fingers_[k].board_finger, renders[k].request});
  return out;
}

}  // namespace palpa::host
