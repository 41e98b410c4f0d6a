// A small SVG line-chart writer for figures and reports (no plotting stack needed).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace palpa::host {

struct Series {
  std::string name;  ///< the legend's entry; empty: drawn but not listed
  std::vector<std::pair<double, double>> points;
  std::string color;  ///< CSS colour; empty picks one
  bool dashed = false;
  bool markers = false;  ///< draw points only (scatter)
  bool joined = false;   ///< with markers: also join the points in order (a family of sizes)
};

/// A stretch of the x axis marked on the plot: a shaded band from x to x_end with a label (e.g.
/// where time is left out), or a vertical line where x_end == x.
struct Marker {
  double x = 0, x_end = 0;
  std::string label;
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  std::vector<Marker> markers;
  double width = 780, height = 420;
  bool log_x = false;
};

/// Text as SVG character data: <, > and & escaped, so a legend like "gap <= 30 %" opens no tag.
std::string SvgEscape(const std::string& text);

/// Renders the chart as a standalone SVG document.
std::string RenderSvg(const Chart& chart);

/// Charts stacked in one SVG document under one title, sharing the x axis's range: quantities
/// in different units (mm, N/mm) each on an axis of their own.
std::string RenderSvgPanels(const std::vector<Chart>& panels, const std::string& title);

}  // namespace palpa::host
