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

struct Chart {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  double width = 780, height = 420;
  bool log_x = false;
};

/// Renders the chart as a standalone SVG document.
std::string RenderSvg(const Chart& chart);

}  // namespace palpa::host
