// Scene files written: the spec as JSON that ParseScene reads back to the same spec.
#include <nlohmann/json.hpp>

#include "palpa/host/scene_file.h"

namespace palpa::host {
namespace {

using nlohmann::json;

json TissueJson(const SceneSpec& s) {
  switch (s.source) {
    case TissueSource::kFile:
      return {{"file", s.tissue_file}};
    case TissueSource::kForceMatrices: {
      json files = json::array();
      for (const ForceMatrixFile& f : s.scan.files)
        files.push_back({{"path", f.path}, {"depth_mm", f.depth_mm}});
      return {{"force_matrices",
               {{"along_line_pitch_mm", s.scan.along_line_pitch_mm},
                {"line_pitch_mm", s.scan.line_pitch_mm},
                {"files", files}}}};
    }
    case TissueSource::kImage:
      return {{"image",
               {{"path", s.image_file},
                {"mm_per_pixel", s.image_scale.mm_per_pixel},
                {"unit", s.image_scale.unit},
                {"value_at_black", s.image_scale.value_at_black},
                {"value_at_white", s.image_scale.value_at_white}}}};
    case TissueSource::kPhantom: {
      const PhantomSpec& p = s.phantom;
      json inclusions = json::array();
      for (const Inclusion& c : p.inclusions) {
        inclusions.push_back({{"name", c.name},
                              {"centre_mm", {c.x_mm, c.y_mm}},
                              {"size_mm", {c.size_x_mm, c.size_y_mm, c.thickness_mm}},
                              {"depth_mm", c.depth_mm},
                              {"stiffness", c.stiffness}});
      }
      json phantom = {{"name", p.name},
                      {"unit", p.unit},
                      {"size_mm", {p.size_x_mm, p.size_y_mm, p.height_mm}},
                      {"background", p.background},
                      {"pitch_mm", p.pitch_mm},
                      {"inclusions", inclusions}};
      if (!p.description.empty()) phantom["description"] = p.description;
      return {{"phantom", phantom}};
    }
    case TissueSource::kPreset:
      break;
  }
  return {{"preset", s.preset}};
}

json LayoutJson(const LayoutSpec& l) {
  json j = {{"kind", l.kind}, {"contact_diameter_mm", l.contact_diameter_mm}};
  if (l.kind == "custom") {
    json places = json::array();
    for (const FingerPlace& p : l.places) places.push_back({p.dx_mm, p.dy_mm});
    j["places_mm"] = places;
  } else {
    j["spacing_mm"] = l.spacing_mm;
  }
  if (l.kind == "row") j["count"] = l.count;
  if (l.angle_deg != 0) j["angle_deg"] = l.angle_deg;
  return j;
}

json RuleJson(const RenderRule& r) {
  json j = {{"contrast", r.contrast}, {"contact_force_n", r.contact_force_n}};
  if (r.value_lo < r.value_hi) j["value_range"] = {r.value_lo, r.value_hi};
  switch (r.pneumatic) {
    case PneumaticMapping::kDeformation:
      j["pneumatic"] = {{"mapping", "deformation"}};
      if (r.deformation_hi_mm > 0)
        j["pneumatic"]["range_mm"] = {r.deformation_lo_mm, r.deformation_hi_mm};
      break;
    case PneumaticMapping::kLevel:
      j["pneumatic"] = {{"mapping", "level"}};
      break;
    case PneumaticMapping::kFingertipStress:
      j["pneumatic"] = {{"mapping", "fingertip-stress"},
                        {"range_kpa", {r.stress_lo_kpa, r.stress_hi_kpa}}};
      break;
  }
  return j;
}

json InputJson(const SceneSpec& s) {
  json j = json::object();
  if (s.tablet) {
    j["tablet"] = {{"pressure_force",
                    {{"a_n", s.tablet->pressure_force.a_n},
                     {"b_per_level", s.tablet->pressure_force.b_per_level}}},
                   {"touch_force_n", s.tablet->touch_force_n}};
  }
  if (s.tactile) {
    const TactileSpec& t = *s.tactile;
    j["tactile"] = {{"elements", t.elements},
                    {"groups", t.groups},
                    {"unit", t.unit},
                    {"value_range", {t.value_lo, t.value_hi}},
                    {"hold_s", t.hold_s}};
  }
  return j;
}

}  // namespace

Result<std::string> SerializeScene(const SceneSpec& s) {
  json j = {{"schema", "palpa-scene"}, {"schema_version", 1}, {"name", s.name}};
  if (!s.description.empty()) j["description"] = s.description;
  j["tissue"] = TissueJson(s);
  j["layout"] = LayoutJson(s.layout);
  j["fingers"] = s.board_fingers;
  j["rule"] = RuleJson(s.rule);
  if (s.tablet || s.tactile) j["input"] = InputJson(s);
  std::string text = j.dump(2) + "\n";
  // What is written must read back: a spec that would not is refused here, not on reading.
  const auto back = ParseScene(text);
  if (!back.ok()) return {back.status, "the scene would not read back: " + back.message};
  return text;
}

}  // namespace palpa::host
