// A tissue's stiffness map: its checks, bilinear interpolation and contact-disc sampling.
#include "palpa/host/scene_tissue.h"
#include "number_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace palpa::host {
namespace {

/// The first value of `grid` that is not finite, by its point; empty when all are.
std::string FirstNonFinite(const TissueMap& map, const std::vector<double>& grid) {
  for (size_t k = 0; k < grid.size(); ++k) {
    if (!std::isfinite(grid[k])) {
      return "point (" + std::to_string(k % map.nx) + ", " + std::to_string(k / map.nx) +
             ") is not a finite number";
    }
  }
  return "";
}

constexpr size_t kMaxRings = 64;

}  // namespace

std::pair<double, double> TissueMap::Range() const {
  if (values.empty()) return {0, 0};
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return {*lo, *hi};
}

Outcome CheckTissue(const TissueMap& map) {
  auto fail = [](const std::string& why) { return Outcome::Fail(Status::kInvalidArgument, why); };
  if (map.nx < 2 || map.ny < 2 || map.nx > kMaxTissuePoints || map.ny > kMaxTissuePoints) {
    return fail("a map has 2 … " + std::to_string(kMaxTissuePoints) +
                " points along each side, not " + std::to_string(map.nx) + " × " +
                std::to_string(map.ny));
  }
  for (const double pitch : {map.pitch_x_mm, map.pitch_y_mm}) {
    if (!std::isfinite(pitch) || pitch <= 0 || pitch > 1000)
      return fail("pitch " + Num(pitch) + " mm is outside (0, 1000] mm");
  }
  if (map.values.size() != map.nx * map.ny) {
    return fail("values: " + std::to_string(map.values.size()) +
                " of them, not nx·ny = " + std::to_string(map.nx * map.ny));
  }
  if (const std::string bad = FirstNonFinite(map, map.values); !bad.empty())
    return fail("values: " + bad);
  if (map.layers.size() > kMaxTissueDepths)
    return fail("more than " + std::to_string(kMaxTissueDepths) + " depth layers");
  double previous = 0;
  for (size_t l = 0; l < map.layers.size(); ++l) {
    const ForceLayer& layer = map.layers[l];
    const std::string at = "depth layer " + std::to_string(l) + " (" + Num(layer.depth_mm) + " mm)";
    if (!std::isfinite(layer.depth_mm) || layer.depth_mm <= previous || layer.depth_mm > 100)
      return fail(at + ": depths rise from above 0 to at most 100 mm");
    previous = layer.depth_mm;
    if (layer.force_n.size() != map.nx * map.ny)
      return fail(at + ": " + std::to_string(layer.force_n.size()) + " forces, not nx·ny");
    if (const std::string bad = FirstNonFinite(map, layer.force_n); !bad.empty())
      return fail(at + ": " + bad);
  }
  return {};
}

bool InterpolateGrid(const TissueMap& map, const std::vector<double>& grid, double x, double y,
                     double* out) {
  if (!(x >= 0 && y >= 0 && x <= map.extent_x_mm() && y <= map.extent_y_mm())) return false;
  const double fx = x / map.pitch_x_mm, fy = y / map.pitch_y_mm;
  const size_t i = std::min(static_cast<size_t>(fx), map.nx - 2);
  const size_t j = std::min(static_cast<size_t>(fy), map.ny - 2);
  const double u = std::clamp(fx - static_cast<double>(i), 0.0, 1.0);
  const double v = std::clamp(fy - static_cast<double>(j), 0.0, 1.0);
  const size_t k = j * map.nx + i;
  const double top = grid[k] + u * (grid[k + 1] - grid[k]);
  const double bottom = grid[k + map.nx] + u * (grid[k + map.nx + 1] - grid[k + map.nx]);
  *out = top + v * (bottom - top);
  return true;
}

ContactSample SampleDisc(const TissueMap& map, double x, double y, double diameter_mm) {
  ContactSample s;
  s.force_n.assign(map.layers.size(), 0.0);
  double total = 0, covered = 0;
  auto add = [&](double px, double py, double weight) {
    total += weight;
    double v = 0;
    if (!InterpolateGrid(map, map.values, px, py, &v)) return;
    covered += weight;
    s.value += weight * v;
    for (size_t l = 0; l < map.layers.size(); ++l) {
      double f = 0;
      InterpolateGrid(map, map.layers[l].force_n, px, py, &f);
      s.force_n[l] += weight * f;
    }
  };
  const double radius = std::isfinite(diameter_mm) ? std::max(0.0, diameter_mm / 2) : 0.0;
  if (radius == 0) {
    add(x, y, 1);
  } else {
    // Rings half a pitch apart, and at least four: a disc spanning a kink of the bilinear
    // surface (a grid line) is not averaged from one ring.
    const double step = std::min({map.pitch_x_mm / 2, map.pitch_y_mm / 2, radius / 4});
    const size_t rings =
        std::clamp(static_cast<size_t>(std::ceil(radius / step)), size_t{1}, kMaxRings);
    const double width = radius / static_cast<double>(rings);
    for (size_t k = 0; k < rings; ++k) {
      const double r = (static_cast<double>(k) + 0.5) * width;
      const double area = std::numbers::pi * width * width * static_cast<double>(2 * k + 1);
      // Points about a ring's width apart: the pattern's cells are near square.
      const size_t n =
          std::max<size_t>(6, static_cast<size_t>(std::ceil(2 * std::numbers::pi * r / width)));
      for (size_t p = 0; p < n; ++p) {
        const double a = 2 * std::numbers::pi * static_cast<double>(p) / static_cast<double>(n);
        add(x + r * std::cos(a), y + r * std::sin(a), area / static_cast<double>(n));
      }
    }
  }
  if (covered > 0) {
    s.value /= covered;
    for (double& f : s.force_n) f /= covered;
  }
  s.coverage = total > 0 ? covered / total : 0;
  return s;
}

}  // namespace palpa::host
