// SVG of a scene: the map as colour cells, a scale bar, the fingers' discs and the input's path.
#include "palpa/host/scene_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "palpa/host/svg_chart.h"

namespace palpa::host {
namespace {

std::string Hundredths(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.2f", v);
  return b;
}

/// Blue → cyan → yellow → red over t in 0 … 1.
std::string Colour(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  double r, g, b;
  if (t < 1.0 / 3) {
    r = 0, g = 3 * t, b = 1;
  } else if (t < 2.0 / 3) {
    r = 3 * t - 1, g = 1, b = 2 - 3 * t;
  } else {
    r = 1, g = 3 - 3 * t, b = 0;
  }
  char out[8];
  std::snprintf(out, sizeof(out), "#%02x%02x%02x", static_cast<int>(std::lround(255 * r)),
                static_cast<int>(std::lround(255 * g)), static_cast<int>(std::lround(255 * b)));
  return out;
}

constexpr size_t kMaxCells = 240;

}  // namespace

std::string SceneSvg(const TissueMap& t, const FingerLayout& layout, double at_x, double at_y,
                     const std::vector<std::pair<double, double>>& path, const std::string& title) {
  const double ex = std::max(t.extent_x_mm(), 1e-9), ey = std::max(t.extent_y_mm(), 1e-9);
  const double scale = std::min(720 / ex, 420 / ey);  // px per mm
  const double left = 40, top = 40, w = ex * scale, h = ey * scale;
  auto X = [&](double x) { return left + x * scale; };
  auto Y = [&](double y) { return top + (ey - y) * scale; };
  const auto [lo, hi] = t.Range();
  std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' width='" + Hundredths(w + 2 * left) +
                    "' height='" + Hundredths(h + top + 90) +
                    "' font-family='sans-serif' font-size='12'>\n";
  svg +=
      "<text x='" + Hundredths(left) + "' y='24' font-size='14'>" + SvgEscape(title) + "</text>\n";
  const size_t step_x = (t.nx + kMaxCells - 1) / kMaxCells,
               step_y = (t.ny + kMaxCells - 1) / kMaxCells;
  for (size_t j = 0; j < t.ny; j += step_y) {
    for (size_t i = 0; i < t.nx; i += step_x) {
      // Each cell centred on its grid point, clipped to the map.
      const double x0 = std::max(0.0, (static_cast<double>(i) - 0.5) * t.pitch_x_mm);
      const double x1 = std::min(ex, (static_cast<double>(i + step_x) - 0.5) * t.pitch_x_mm);
      const double y0 = std::max(0.0, (static_cast<double>(j) - 0.5) * t.pitch_y_mm);
      const double y1 = std::min(ey, (static_cast<double>(j + step_y) - 0.5) * t.pitch_y_mm);
      const double v = hi > lo ? (t.At(i, j) - lo) / (hi - lo) : 0;
      svg += "<rect x='" + Hundredths(X(x0)) + "' y='" + Hundredths(Y(y1)) + "' width='" +
             Hundredths((x1 - x0) * scale + 0.3) + "' height='" +
             Hundredths((y1 - y0) * scale + 0.3) + "' fill='" + Colour(v) + "'/>\n";
    }
  }
  svg += "<rect x='" + Hundredths(left) + "' y='" + Hundredths(top) + "' width='" + Hundredths(w) +
         "' height='" + Hundredths(h) + "' fill='none' stroke='#333'/>\n";
  if (path.size() > 1) {
    svg += "<polyline fill='none' stroke='#000' stroke-width='1.2' points='";
    for (const auto& [x, y] : path) svg += Hundredths(X(x)) + "," + Hundredths(Y(y)) + " ";
    svg += "'/>\n";
  }
  const double r = std::max(layout.contact_diameter_mm / 2 * scale, 3.0);
  for (size_t f = 0; f < layout.fingers.size(); ++f) {
    const double cx = X(at_x + layout.fingers[f].dx_mm), cy = Y(at_y + layout.fingers[f].dy_mm);
    svg += "<circle cx='" + Hundredths(cx) + "' cy='" + Hundredths(cy) + "' r='" + Hundredths(r) +
           "' fill='none' stroke='#000' stroke-width='1.5'/>\n<text x='" + Hundredths(cx + r + 2) +
           "' y='" + Hundredths(cy - r) + "'>" + std::to_string(f + 1) + "</text>\n";
  }
  // Scale bar: the colours from the smallest to the largest value, and the axes' extent.
  const double bar_y = top + h + 30;
  for (int k = 0; k < 100; ++k) {
    svg += "<rect x='" + Hundredths(left + k * 3.0) + "' y='" + Hundredths(bar_y) +
           "' width='3.3' height='12' fill='" + Colour(k / 99.0) + "'/>\n";
  }
  char range[128];
  std::snprintf(range, sizeof(range), "%g … %g %s", lo, hi, t.unit.c_str());
  svg += "<text x='" + Hundredths(left + 310) + "' y='" + Hundredths(bar_y + 11) + "'>" +
         SvgEscape(range) + "</text>\n<text x='" + Hundredths(left) + "' y='" +
         Hundredths(top + h + 16) + "'>x 0 … " + Hundredths(ex) + " mm, y 0 … " + Hundredths(ey) +
         " mm</text>\n</svg>\n";
  return svg;
}

}  // namespace palpa::host
