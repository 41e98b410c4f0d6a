// SVG rendering of line and scatter charts with axes, ticks and a legend.
#include "palpa/host/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace palpa::host {
namespace {

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                "#9467bd", "#8c564b", "#17becf", "#7f7f7f"};

std::string Tenths(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.1f", v);
  return b;
}

std::string Label(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%g", std::fabs(v) < 1e-12 ? 0.0 : v);
  return b;
}

/// About `count` round tick values covering [lo, hi].
std::vector<double> Ticks(double lo, double hi, int count) {
  const double raw = (hi - lo) / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step) ticks.push_back(t);
  return ticks;
}

}  // namespace

/// Text as SVG character data: a legend like "gap <= 30 %" must not open a tag.
std::string SvgEscape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

namespace {

struct Range {
  double x0 = std::numeric_limits<double>::max(), x1 = -std::numeric_limits<double>::max();
};

double AxisX(const Chart& c, double x) { return c.log_x ? std::log10(x) : x; }

Range XRange(const Chart& c) {
  Range r;
  for (const Series& s : c.series) {
    for (const auto& point : s.points) {
      r.x0 = std::min(r.x0, AxisX(c, point.first));
      r.x1 = std::max(r.x1, AxisX(c, point.first));
    }
  }
  return r;
}

std::string Header(double width, double height) {
  return "<svg xmlns='http://www.w3.org/2000/svg' width='" + Tenths(width) + "' height='" +
         Tenths(height) +
         "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' "
         "fill='white'/>\n";
}

/// One chart's axes, series, markers and legend, its top edge at `offset_y`, over the x range
/// [x0, x1] (in axis units); its title only when `titled`.
void DrawPanel(std::string& svg, const Chart& c, double offset_y, double x0, double x1,
               bool titled) {
  double y0 = std::numeric_limits<double>::max(), y1 = -y0;
  for (const Series& s : c.series) {
    for (const auto& [x, y] : s.points) {
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  }
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const double pad_y = 0.05 * (y1 - y0);
  y0 -= pad_y;
  y1 += pad_y;
  const double left = 70, right = 230, top = offset_y + (titled ? 40 : 14), bottom = 50;
  const double pw = c.width - left - right, ph = offset_y + c.height - top - bottom;
  auto px = [&](double x) { return left + (AxisX(c, x) - x0) / (x1 - x0) * pw; };
  auto py = [&](double y) { return top + (1 - (y - y0) / (y1 - y0)) * ph; };
  if (titled) {
    svg += "<text x='" + Tenths(c.width / 2) + "' y='" + Tenths(offset_y + 22) +
           "' text-anchor='middle' font-size='14'>" + SvgEscape(c.title) + "</text>\n";
  }
  for (const Marker& m : c.markers) {  // behind the data
    const double a = std::clamp(px(m.x), left, left + pw);
    const double b = std::clamp(px(m.x_end), left, left + pw);
    if (b > a + 0.5) {
      svg += "<rect x='" + Tenths(a) + "' y='" + Tenths(top) + "' width='" + Tenths(b - a) +
             "' height='" + Tenths(ph) + "' fill='#f2f2f2'/>";
    } else {
      svg += "<line x1='" + Tenths(a) + "' y1='" + Tenths(top) + "' x2='" + Tenths(a) + "' y2='" +
             Tenths(top + ph) + "' stroke='#888' stroke-dasharray='2,3'/>";
    }
    svg += "<text x='" + Tenths((a + b) / 2) + "' y='" + Tenths(top + 14) +
           "' text-anchor='middle' fill='#555' font-size='11'>" + SvgEscape(m.label) + "</text>\n";
  }
  svg += "<rect x='" + Tenths(left) + "' y='" + Tenths(top) + "' width='" + Tenths(pw) +
         "' height='" + Tenths(ph) + "' fill='none' stroke='#444'/>\n";
  // A log axis is labelled at 1, 2 and 5 of each decade (round numbers a reader can place).
  std::vector<double> x_ticks;
  if (c.log_x) {
    for (int decade = static_cast<int>(std::floor(x0)); decade <= static_cast<int>(std::ceil(x1));
         ++decade) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double t = decade + std::log10(m);
        if (t >= x0 - 1e-9 && t <= x1 + 1e-9) x_ticks.push_back(t);
      }
    }
  }
  if (x_ticks.size() < 2) x_ticks = Ticks(x0, x1, 8);
  for (double t : x_ticks) {
    const double x = left + (t - x0) / (x1 - x0) * pw;
    svg += "<line x1='" + Tenths(x) + "' y1='" + Tenths(top) + "' x2='" + Tenths(x) + "' y2='" +
           Tenths(top + ph) + "' stroke='#eee'/>";
    svg += "<text x='" + Tenths(x) + "' y='" + Tenths(top + ph + 16) + "' text-anchor='middle'>" +
           Label(c.log_x ? std::pow(10.0, t) : t) + "</text>\n";
  }
  for (double t : Ticks(y0, y1, 6)) {
    const double y = py(t);
    svg += "<line x1='" + Tenths(left) + "' y1='" + Tenths(y) + "' x2='" + Tenths(left + pw) +
           "' y2='" + Tenths(y) + "' stroke='#eee'/>";
    svg += "<text x='" + Tenths(left - 6) + "' y='" + Tenths(y + 4) + "' text-anchor='end'>" +
           Label(t) + "</text>\n";
  }
  svg += "<text x='" + Tenths(left + pw / 2) + "' y='" + Tenths(offset_y + c.height - 10) +
         "' text-anchor='middle'>" + SvgEscape(c.x_label) + "</text>\n";
  svg += "<text transform='translate(16," + Tenths(top + ph / 2) +
         ") rotate(-90)' text-anchor='middle'>" + SvgEscape(c.y_label) + "</text>\n";
  size_t listed = 0;  // legend entries so far
  for (size_t i = 0; i < c.series.size(); ++i) {
    const Series& s = c.series[i];
    const std::string color = s.color.empty() ? kPalette[i % 8] : s.color;
    auto polyline = [&](const char* width, bool dashed) {
      svg += "<polyline fill='none' stroke='" + color + "' stroke-width='" + width + "'" +
             (dashed ? std::string(" stroke-dasharray='6,4'") : std::string()) + " points='";
      for (const auto& [x, y] : s.points) svg += Tenths(px(x)) + "," + Tenths(py(y)) + " ";
      svg += "'/>\n";
    };
    if (s.markers) {
      if (s.joined) polyline("1", false);
      for (const auto& [x, y] : s.points) {
        svg += "<circle cx='" + Tenths(px(x)) + "' cy='" + Tenths(py(y)) + "' r='4' fill='" +
               color + "'/>";
      }
    } else {
      polyline("1.6", s.dashed);
    }
    if (s.name.empty()) continue;  // drawn, not listed (e.g. a second part of a named series)
    const double ly = top + 14 + 18 * static_cast<double>(listed++);
    svg += "<line x1='" + Tenths(left + pw + 12) + "' y1='" + Tenths(ly - 4) + "' x2='" +
           Tenths(left + pw + 34) + "' y2='" + Tenths(ly - 4) + "' stroke='" + color +
           "' stroke-width='3'" +
           (s.dashed ? std::string(" stroke-dasharray='6,4'") : std::string()) + "/>";
    svg += "<text x='" + Tenths(left + pw + 40) + "' y='" + Tenths(ly) + "'>" + SvgEscape(s.name) +
           "</text>\n";
  }
}

}  // namespace

std::string RenderSvg(const Chart& c) {
  const Range r = XRange(c);
  std::string svg = Header(c.width, c.height);
  DrawPanel(svg, c, 0, r.x0, r.x1, true);
  return svg + "</svg>\n";
}

std::string RenderSvgPanels(const std::vector<Chart>& panels, const std::string& title) {
  Range shared;
  double width = 0, height = 34;
  for (const Chart& c : panels) {
    const Range r = XRange(c);
    shared.x0 = std::min(shared.x0, r.x0);
    shared.x1 = std::max(shared.x1, r.x1);
    width = std::max(width, c.width);
    height += c.height;
  }
  std::string svg = Header(width, height);
  svg += "<text x='" + Tenths(width / 2) + "' y='22' text-anchor='middle' font-size='14'>" +
         SvgEscape(title) + "</text>\n";
  double offset = 34;
  for (const Chart& c : panels) {
    DrawPanel(svg, c, offset, shared.x0, shared.x1, false);
    offset += c.height;
  }
  return svg + "</svg>\n";
}

}  // namespace palpa::host
