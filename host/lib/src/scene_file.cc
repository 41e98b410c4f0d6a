// Scene files: parsing with the failing field named, writing them back, and the tissue they name.
#include "palpa/host/scene_file.h"

#include <cmath>
#include <cstdio>
#include <tuple>

#include "number_text.h"
#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

using nlohmann::json;

/// A pair of numbers [a, b] within lo … hi (a range, or a point in the plane).
std::pair<double, double> Pair(const JsonObject& o, const char* key, double lo, double hi) {
  const json& v = o.List(key, 2, 2);
  for (size_t k = 0; k < 2; ++k) {
    if (!v[k].is_number() || !(v[k].get<double>() >= lo && v[k].get<double>() <= hi)) {
      throw JsonInvalid(o.Item(key, k) + ": must be a number within " + Num(lo) + " … " + Num(hi));
    }
  }
  return {v[0].get<double>(), v[1].get<double>()};
}

/// Three positive sizes [x, y, z] in mm.
void Sizes(const JsonObject& o, const char* key, double* x, double* y, double* z) {
  const json& v = o.List(key, 3, 3);
  double* out[] = {x, y, z};
  for (size_t k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !(v[k].get<double>() > 0))
      throw JsonInvalid(o.Item(key, k) + ": must be a number of mm above 0");
    *out[k] = v[k].get<double>();
  }
}

std::string Resolve(const std::string& base, const std::string& path) {
  return base.empty() || path.front() == '/' ? path : base + "/" + path;
}

PhantomSpec ParsePhantom(const json& j) {
  const JsonObject o(
      j, "tissue.phantom",
      {"name", "description", "unit", "size_mm", "background", "pitch_mm", "inclusions"});
  PhantomSpec s;
  s.name = o.Text("name");
  if (o.Has("description")) s.description = o.Text("description");
  s.unit = o.Text("unit");
  Sizes(o, "size_mm", &s.size_x_mm, &s.size_y_mm, &s.height_mm);
  s.background = o.Number("background", 1e-12, 1e9);
  s.pitch_mm = o.Number("pitch_mm", 1e-3, 1000);
  const json& list = o.List("inclusions", 0, 64);
  for (size_t k = 0; k < list.size(); ++k) {
    const JsonObject c(list[k], o.Item("inclusions", k),
                       {"name", "centre_mm", "size_mm", "depth_mm", "stiffness"});
    Inclusion in;
    in.name = c.Text("name");
    std::tie(in.x_mm, in.y_mm) = Pair(c, "centre_mm", -1e4, 1e4);
    Sizes(c, "size_mm", &in.size_x_mm, &in.size_y_mm, &in.thickness_mm);
    in.depth_mm = c.Number("depth_mm", 0, 1e4);
    in.stiffness = c.Number("stiffness", 1e-12, 1e9);
    s.inclusions.push_back(in);
  }
  // Fit and overlap are the phantom's own checks, named by field as here.
  if (const Outcome ok = CheckPhantom(s); !ok.ok())
    throw JsonInvalid("tissue.phantom." + ok.message);
  return s;
}

void ParseTissueSource(const JsonObject& doc, const std::string& base, SceneSpec* s) {
  const JsonObject t(doc.At("tissue"), "tissue",
                     {"preset", "file", "force_matrices", "image", "phantom"});
  const int given =
      t.Has("preset") + t.Has("file") + t.Has("force_matrices") + t.Has("image") + t.Has("phantom");
  if (given != 1) {
    throw JsonInvalid(
        "tissue: must hold exactly one of preset, file, force_matrices, image, phantom");
  }
  if (t.Has("preset")) {
    s->source = TissueSource::kPreset;
    s->preset = t.Text("preset");
    if (s->preset != ThreeCubePhantom().name)
      throw JsonInvalid("tissue.preset: \"" + s->preset + "\" is not a preset (thesis-three-cube)");
  } else if (t.Has("file")) {
    s->source = TissueSource::kFile;
    s->tissue_file = Resolve(base, t.Text("file"));
  } else if (t.Has("image")) {
    s->source = TissueSource::kImage;
    const JsonObject i(t.At("image"), "tissue.image",
                       {"path", "mm_per_pixel", "unit", "value_at_black", "value_at_white"});
    s->image_file = Resolve(base, i.Text("path"));
    s->image_scale = {s->name, i.Text("unit"), i.Number("mm_per_pixel", 1e-3, 1000),
                      i.Number("value_at_black", -1e12, 1e12),
                      i.Number("value_at_white", -1e12, 1e12)};
  } else if (t.Has("phantom")) {
    s->source = TissueSource::kPhantom;
    s->phantom = ParsePhantom(t.At("phantom"));
  } else {
    s->source = TissueSource::kForceMatrices;
    const JsonObject m(t.At("force_matrices"), "tissue.force_matrices",
                       {"along_line_pitch_mm", "line_pitch_mm", "files"});
    s->scan.name = s->name;
    s->scan.along_line_pitch_mm = m.Number("along_line_pitch_mm", 1e-3, 1000);
    s->scan.line_pitch_mm = m.Number("line_pitch_mm", 1e-3, 1000);
    const json& files = m.List("files", 1, kMaxTissueDepths);
    for (size_t k = 0; k < files.size(); ++k) {
      const JsonObject f(files[k], m.Item("files", k), {"path", "depth_mm"});
      s->scan.files.push_back({Resolve(base, f.Text("path")), f.Number("depth_mm", 1e-3, 100)});
    }
  }
}

LayoutSpec ParseLayout(const JsonObject& doc) {
  const JsonObject o(
      doc.At("layout"), "layout",
      {"kind", "spacing_mm", "count", "places_mm", "angle_deg", "contact_diameter_mm"});
  LayoutSpec l;
  l.kind = o.Choice("kind", {"right-triangle", "row", "jamming-pair", "custom"});
  if (l.kind == "custom") {
    const json& places = o.List("places_mm", 1, kMaxLayoutFingers);
    for (size_t k = 0; k < places.size(); ++k) {
      const std::string at = o.Item("places_mm", k);
      if (!places[k].is_array() || places[k].size() != 2 || !places[k][0].is_number() ||
          !places[k][1].is_number() || std::fabs(places[k][0].get<double>()) > 500 ||
          std::fabs(places[k][1].get<double>()) > 500) {
        throw JsonInvalid(at + ": must be [dx, dy], each within ±500 mm");
      }
      l.places.push_back({places[k][0].get<double>(), places[k][1].get<double>()});
    }
  } else {
    l.spacing_mm = o.Number("spacing_mm", 0, 500);
    if (l.kind == "row") l.count = static_cast<size_t>(o.Integer("count", 1, kMaxLayoutFingers));
  }
  if (o.Has("angle_deg")) l.angle_deg = o.Number("angle_deg", -360, 360);
  l.contact_diameter_mm = o.Number("contact_diameter_mm", 0, 100);
  return l;
}

RenderRule ParseRule(const JsonObject& doc) {
  const JsonObject o(doc.At("rule"), "rule",
                     {"value_range", "contrast", "contact_force_n", "pneumatic"});
  RenderRule r;
  if (o.Has("value_range")) {
    std::tie(r.value_lo, r.value_hi) = Pair(o, "value_range", -1e12, 1e12);
    if (!(r.value_lo < r.value_hi)) throw JsonInvalid("rule.value_range: must rise (lo < hi)");
  }
  r.contrast = o.Number("contrast", 0.01, 10);
  r.contact_force_n = o.Number("contact_force_n", 0, kMaxInputForceN);
  const JsonObject p(o.At("pneumatic"), "rule.pneumatic", {"mapping", "range_mm", "range_kpa"});
  const std::string mapping = p.Choice("mapping", {"deformation", "level", "fingertip-stress"});
  if (mapping == "deformation") {
    r.pneumatic = PneumaticMapping::kDeformation;
    if (p.Has("range_mm"))
      std::tie(r.deformation_lo_mm, r.deformation_hi_mm) = Pair(p, "range_mm", 0, 100);
  } else if (mapping == "level") {
    r.pneumatic = PneumaticMapping::kLevel;
  } else {
    r.pneumatic = PneumaticMapping::kFingertipStress;
    if (p.Has("range_kpa"))
      std::tie(r.stress_lo_kpa, r.stress_hi_kpa) = Pair(p, "range_kpa", 0, 1000);
  }
  if (mapping != "deformation" && p.Has("range_mm"))
    throw JsonInvalid("rule.pneumatic.range_mm: only the deformation mapping has one");
  if (mapping != "fingertip-stress" && p.Has("range_kpa"))
    throw JsonInvalid("rule.pneumatic.range_kpa: only the fingertip-stress mapping has one");
  return r;
}

void ParseInput(const JsonObject& doc, SceneSpec* s) {
  const JsonObject in(doc.At("input"), "input", {"tablet", "tactile"});
  if (in.Has("tablet")) {
    const JsonObject t(in.At("tablet"), "input.tablet", {"pressure_force", "touch_force_n"});
    TabletSpec tablet;
    if (t.Has("pressure_force")) {
      const JsonObject p(t.At("pressure_force"), "input.tablet.pressure_force",
                         {"a_n", "b_per_level"});
      tablet.pressure_force = {p.Number("a_n", 1e-6, 100), p.Number("b_per_level", -0.1, 0.1)};
      if (const Outcome ok = CheckPressureForce(tablet.pressure_force); !ok.ok())
        throw JsonInvalid("input.tablet." + ok.message);
    }
    if (t.Has("touch_force_n"))
      tablet.touch_force_n = t.Number("touch_force_n", 0, kMaxInputForceN);
    s->tablet = tablet;
  }
  if (in.Has("tactile")) {
    const JsonObject t(in.At("tactile"), "input.tactile",
                       {"elements", "groups", "unit", "value_range", "hold_s"});
    TactileSpec tactile;
    tactile.elements = static_cast<size_t>(t.Integer("elements", 1, kMaxTactileElements));
    const json& groups = t.List("groups", 1, kMaxLayoutFingers);
    for (size_t g = 0; g < groups.size(); ++g) {
      const std::string at = t.Item("groups", g);
      if (!groups[g].is_array() || groups[g].empty() || groups[g].size() > kMaxTactileElements)
        throw JsonInvalid(at + ": must be a list of 1 … " + std::to_string(kMaxTactileElements) +
                          " element indices");
      std::vector<size_t> group;
      for (size_t k = 0; k < groups[g].size(); ++k) {
        const json& e = groups[g][k];
        if (!e.is_number_integer() || e.get<long>() < 0)
          throw JsonInvalid(at + "[" + std::to_string(k) +
                            "]: must be an element index, 0 or more");
        group.push_back(static_cast<size_t>(e.get<long>()));
      }
      tactile.groups.push_back(std::move(group));
    }
    tactile.unit = t.Text("unit");
    std::tie(tactile.value_lo, tactile.value_hi) = Pair(t, "value_range", -1e12, 1e12);
    if (t.Has("hold_s")) tactile.hold_s = t.Number("hold_s", 0, kMaxTactileHoldS);
    const size_t fingers = MakeLayout(s->layout).fingers.size();
    if (const Outcome ok = CheckTactile(tactile, fingers); !ok.ok())
      throw JsonInvalid("input." + ok.message);
    s->tactile = tactile;
  }
}

SceneSpec Parse(const json& j, const std::string& base) {
  const JsonObject doc(j, "",
                       {"schema", "schema_version", "name", "description", "tissue", "layout",
                        "fingers", "rule", "input"});
  if (doc.Text("schema") != "palpa-scene") throw JsonInvalid("schema: must be \"palpa-scene\"");
  doc.Integer("schema_version", 1, 1);
  SceneSpec s;
  s.name = doc.Text("name");
  if (doc.Has("description")) s.description = doc.Text("description");
  ParseTissueSource(doc, base, &s);
  s.layout = ParseLayout(doc);
  const size_t places = MakeLayout(s.layout).fingers.size();
  const json& fingers = doc.List("fingers", places, places);
  for (size_t k = 0; k < fingers.size(); ++k) {
    if (!fingers[k].is_number_integer() || fingers[k].get<long>() < 0 ||
        fingers[k].get<long>() >= static_cast<long>(protocol::kMaxFingers)) {
      throw JsonInvalid(doc.Item("fingers", k) + ": must be a board finger, 0 … " +
                        std::to_string(protocol::kMaxFingers - 1));
    }
    const auto f = static_cast<uint8_t>(fingers[k].get<long>());
    for (size_t other = 0; other < k; ++other) {
      if (s.board_fingers[other] == f) {
        throw JsonInvalid(doc.Item("fingers", k) + ": board finger " + std::to_string(f) +
                          " is fingers[" + std::to_string(other) + "] already");
      }
    }
    s.board_fingers.push_back(f);
  }
  s.rule = ParseRule(doc);
  if (const Outcome ok = CheckRule(s.rule); !ok.ok()) throw JsonInvalid(ok.message);
  if (doc.Has("input")) ParseInput(doc, &s);
  return s;
}

}  // namespace

std::vector<std::string> ScenePresets() { return {ThreeCubePhantom().name}; }

FingerLayout MakeLayout(const LayoutSpec& l) {
  FingerLayout layout;
  if (l.kind == "right-triangle") {
    layout = RightTriangleLayout(l.spacing_mm, l.contact_diameter_mm);
  } else if (l.kind == "row") {
    layout = RowLayout(l.count, l.spacing_mm, l.contact_diameter_mm);
  } else if (l.kind == "jamming-pair") {
    layout = JammingPairLayout(l.spacing_mm, l.contact_diameter_mm);
  } else {
    layout = {"custom", l.places, l.contact_diameter_mm};
  }
  return l.angle_deg != 0 ? Rotated(layout, l.angle_deg) : layout;
}

Result<SceneSpec> ParseScene(const std::string& text, const std::string& base_dir) {
  return ParseJsonWith<SceneSpec>(text, [&](const json& j) { return Parse(j, base_dir); });
}

Result<SceneSpec> LoadScene(const std::string& path) {
  const size_t slash = path.rfind('/');
  const std::string base = slash == std::string::npos ? "" : path.substr(0, slash);
  return ReadAndParse(path, kSceneFileLimits,
                      [&](const std::string& text) { return ParseScene(text, base); });
}

Result<TissueMap> LoadSceneTissue(const SceneSpec& s) {
  switch (s.source) {
    case TissueSource::kFile:
      return LoadTissue(s.tissue_file);
    case TissueSource::kForceMatrices:
      return LoadForceMatrices(s.scan);
    case TissueSource::kImage:
      return LoadTissueImage(s.image_file, s.image_scale);
    case TissueSource::kPhantom:
      return GeneratePhantom(s.phantom);
    case TissueSource::kPreset:
      break;
  }
  if (s.preset == ThreeCubePhantom().name) return GeneratePhantom(ThreeCubePhantom());
  return {Status::kNotFound, "no tissue preset \"" + s.preset + "\""};
}

}  // namespace palpa::host
