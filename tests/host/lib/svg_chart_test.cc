// SVG charts: text that holds markup characters is escaped, so the document stays well-formed;
// the legend lists the named series, with a dashed swatch for a dashed one.
#include <cctype>
#include <string>

#include "CppUTest/TestHarness.h"
#include "palpa/host/svg_chart.h"

namespace ph = palpa::host;

TEST_GROUP(SvgChart){};

TEST(SvgChart, LegendsTitlesAndAxisLabelsWithMarkupCharactersAreEscaped) {
  ph::Chart chart;
  chart.title = "error < 5 % & cost > 0";
  chart.x_label = "instructions <per step>";
  chart.y_label = "gap & residual";
  chart.series.push_back({"goal: gap <= 30 %", {{0, 1}, {1, 2}}, "", true, false});
  const std::string svg = ph::RenderSvg(chart);
  CHECK(svg.find("goal: gap &lt;= 30 %") != std::string::npos);
  CHECK(svg.find("error &lt; 5 % &amp; cost &gt; 0") != std::string::npos);
  CHECK(svg.find("instructions &lt;per step&gt;") != std::string::npos);
  CHECK(svg.find("gap &amp; residual") != std::string::npos);
  // Every '<' opens a tag or a declaration, every '&' an entity.
  for (size_t i = 0; i < svg.size(); ++i) {
    if (svg[i] == '<') {
      const char next = i + 1 < svg.size() ? svg[i + 1] : '\0';
      CHECK_TEXT(std::isalpha(static_cast<unsigned char>(next)) || next == '/' || next == '?' ||
                     next == '!',
                 svg.substr(i, 20).c_str());
    }
    if (svg[i] == '&') {
      const size_t end = svg.find(';', i);
      CHECK_TEXT(end != std::string::npos && end - i <= 5, svg.substr(i, 20).c_str());
    }
  }
}

TEST(SvgChart, UnnamedSeriesAreDrawnButNotListed) {
  ph::Chart chart;
  chart.series.push_back({"first", {{0, 1}, {1, 2}}, "#111111", false, false});
  chart.series.push_back({"", {{2, 1}, {3, 2}}, "#111111", false, false});
  chart.series.push_back({"target", {{0, 0}, {3, 0}}, "#222222", true, false});
  const std::string svg = ph::RenderSvg(chart);
  auto count = [&svg](const std::string& what) {
    size_t n = 0;
    for (size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  LONGS_EQUAL(3, count("<polyline"));
  LONGS_EQUAL(2, count("stroke-width='3'"));  // legend swatches: the named series only
  // The dashed series' swatch is dashed too: its line and its swatch.
  LONGS_EQUAL(2, count("stroke-dasharray"));
}

TEST(SvgChart, PanelsShareTheTimeAxisEachWithItsOwnUnitAndMarksWhatIsLeftOut) {
  // The demo chart: mm and N/mm are not one axis; the calibration's time left out is shown.
  ph::Chart mm, stiffness;
  mm.y_label = "deformation (mm)";
  mm.series.push_back({"finger 1", {{0, 0.1}, {10, 1.2}}, "", false, false});
  mm.markers.push_back({4, 6, "23 s of calibration left out"});
  stiffness.y_label = "stiffness (N/mm)";
  stiffness.series.push_back({"finger 4", {{2, 0.7}, {8, 1.3}}, "", false, false});
  const std::string svg = ph::RenderSvgPanels({mm, stiffness}, "demo");
  CHECK(svg.find("deformation (mm)") != std::string::npos);
  CHECK(svg.find("stiffness (N/mm)") != std::string::npos);
  CHECK(svg.find("23 s of calibration left out") != std::string::npos);
  CHECK(svg.find("fill='#f2f2f2'") != std::string::npos);  // the band
  // One x range for both: finger 4's first point (x = 2) is a fifth of the way along, not at
  // the left edge as it would be on an axis of its own.
  const size_t second = svg.find("<polyline", svg.find("<polyline") + 1);
  const size_t points = svg.find("points='", second) + 8;
  const double x = std::stod(svg.substr(points, svg.find(',', points) - points));
  const double left = 70, width = 780 - 70 - 230;
  DOUBLES_EQUAL(left + width * 0.2, x, 0.2);
}
