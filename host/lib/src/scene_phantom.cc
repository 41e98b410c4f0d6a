// Generated phantoms: checks, the series-column surface stiffness, the three-cube preset.
#include "palpa/host/scene_phantom.h"
#include "number_text.h"

#include <cmath>
#include <cstdio>

namespace palpa::host {
namespace {

bool Positive(double v, double hi) { return std::isfinite(v) && v > 0 && v <= hi; }

bool Inside(const Inclusion& c, double x, double y) {
  return std::fabs(x - c.x_mm) <= c.size_x_mm / 2 && std::fabs(y - c.y_mm) <= c.size_y_mm / 2;
}

/// Two boxes share volume: their footprints and their vertical extents overlap.
bool Overlap(const Inclusion& a, const Inclusion& b) {
  const bool plan = std::fabs(a.x_mm - b.x_mm) < (a.size_x_mm + b.size_x_mm) / 2 &&
                    std::fabs(a.y_mm - b.y_mm) < (a.size_y_mm + b.size_y_mm) / 2;
  const bool column =
      a.depth_mm < b.depth_mm + b.thickness_mm && b.depth_mm < a.depth_mm + a.thickness_mm;
  return plan && column;
}

}  // namespace

Outcome CheckPhantom(const PhantomSpec& s) {
  auto fail = [](const std::string& why) { return Outcome::Fail(Status::kInvalidArgument, why); };
  if (s.name.empty() || s.unit.empty()) return fail("a phantom needs a name and a unit");
  const std::pair<const char*, double> sizes[] = {
      {"size_x_mm", s.size_x_mm}, {"size_y_mm", s.size_y_mm}, {"height_mm", s.height_mm}};
  for (const auto& [field, v] : sizes) {
    if (!Positive(v, 10000))
      return fail(std::string(field) + ": " + Num(v) + " is not in (0, 10000] mm");
  }
  if (!Positive(s.background, 1e9))
    return fail("background: " + Num(s.background) + " is not above 0");
  if (!Positive(s.pitch_mm, 1000)) return fail("pitch_mm: " + Num(s.pitch_mm) + " is not above 0");
  for (const double size : {s.size_x_mm, s.size_y_mm}) {
    const double points = std::round(size / s.pitch_mm) + 1;
    if (points < 2 || points > static_cast<double>(kMaxTissuePoints)) {
      return fail("pitch_mm: " + Num(s.pitch_mm) + " mm over " + Num(size) + " mm makes " +
                  Num(points) + " points on a side, not 2 … " + std::to_string(kMaxTissuePoints));
    }
  }
  if (s.inclusions.size() > 64) return fail("inclusions: more than 64");
  for (size_t k = 0; k < s.inclusions.size(); ++k) {
    const Inclusion& c = s.inclusions[k];
    const std::string at = "inclusions[" + std::to_string(k) + "]";
    const std::pair<const char*, double> dims[] = {
        {"size_x_mm", c.size_x_mm}, {"size_y_mm", c.size_y_mm}, {"thickness_mm", c.thickness_mm}};
    for (const auto& [field, v] : dims) {
      if (!Positive(v, 10000)) return fail(at + "." + field + ": " + Num(v) + " is not above 0");
    }
    if (!Positive(c.stiffness, 1e9))
      return fail(at + ".stiffness: " + Num(c.stiffness) + " is not above 0");
    if (!std::isfinite(c.x_mm) || c.x_mm - c.size_x_mm / 2 < 0 ||
        c.x_mm + c.size_x_mm / 2 > s.size_x_mm)
      return fail(at + ".x_mm: " + Num(c.x_mm) + " puts it outside the block (0 … " +
                  Num(s.size_x_mm) + " mm)");
    if (!std::isfinite(c.y_mm) || c.y_mm - c.size_y_mm / 2 < 0 ||
        c.y_mm + c.size_y_mm / 2 > s.size_y_mm)
      return fail(at + ".y_mm: " + Num(c.y_mm) + " puts it outside the block (0 … " +
                  Num(s.size_y_mm) + " mm)");
    if (!std::isfinite(c.depth_mm) || c.depth_mm < 0 || c.depth_mm + c.thickness_mm > s.height_mm) {
      return fail(at + ".depth_mm: " + Num(c.depth_mm) + " + thickness " + Num(c.thickness_mm) +
                  " mm does not fit in the block's height of " + Num(s.height_mm) + " mm");
    }
    for (size_t other = 0; other < k; ++other) {
      if (Overlap(c, s.inclusions[other]))
        return fail(at + ": overlaps inclusions[" + std::to_string(other) + "]");
    }
  }
  return {};
}

Result<TissueMap> GeneratePhantom(const PhantomSpec& s) {
  if (Outcome ok = CheckPhantom(s); !ok.ok()) {
    ok.message =
        "phantom " + (s.name.empty() ? std::string("(unnamed)") : s.name) + ": " + ok.message;
    return ok;
  }
  TissueMap map;
  map.name = s.name;
  map.unit = s.unit;
  map.nx = static_cast<size_t>(std::round(s.size_x_mm / s.pitch_mm)) + 1;
  map.ny = static_cast<size_t>(std::round(s.size_y_mm / s.pitch_mm)) + 1;
  // The grid spans the block exactly: the pitch is adjusted to the nearest that divides it.
  map.pitch_x_mm = s.size_x_mm / static_cast<double>(map.nx - 1);
  map.pitch_y_mm = s.size_y_mm / static_cast<double>(map.ny - 1);
  map.values.resize(map.nx * map.ny);
  for (size_t j = 0; j < map.ny; ++j) {
    for (size_t i = 0; i < map.nx; ++i) {
      const double x = static_cast<double>(i) * map.pitch_x_mm;
      const double y = static_cast<double>(j) * map.pitch_y_mm;
      double background = s.height_mm, compliance = 0;  // Σ thickness / stiffness
      for (const Inclusion& c : s.inclusions) {
        if (!Inside(c, x, y)) continue;
        background -= c.thickness_mm;
        compliance += c.thickness_mm / c.stiffness;
      }
      compliance += background / s.background;
      map.values[j * map.nx + i] = s.height_mm / compliance;
    }
  }
  return map;
}

PhantomSpec ThreeCubePhantom() {
  PhantomSpec s;
  s.name = "thesis-three-cube";
  s.description =
      "Thesis §5.3.4.2: a silicone phantom with plastic cubes A, B, C 4, 12 and 8 mm thick. The "
      "block's 120 × 30 mm is read from the map's axes (Fig, approximate). palpa's choices where "
      "the thesis is silent: a 20 mm high block of RTV6166 1:2 at E = 14.7 kPa (Phantom III's "
      "matrix), cubes of E = 1590 kPa (the thesis's plastic-eraser inclusions), centred at "
      "x = 30, 60, 90 mm on the mid-line, tops 3 mm below the surface (the shallowest nodule "
      "depth the thesis used).";
  s.unit = "kPa";
  s.size_x_mm = 120;
  s.size_y_mm = 30;
  s.height_mm = 20;
  s.background = 14.7;
  s.pitch_mm = 0.5;
  const double sides[] = {4, 12, 8};
  const char* names[] = {"A", "B", "C"};
  for (int k = 0; k < 3; ++k) {
    s.inclusions.push_back({names[k], 30.0 * (k + 1), 15, sides[k], sides[k], sides[k], 3, 1590});
  }
  return s;
}

}  // namespace palpa::host
