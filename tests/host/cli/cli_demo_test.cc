// ./run demo's main job end to end through palpa demo: nominal fingers show their loops,
// calibrated ones follow their targets.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>

#include "cli_fixtures.h"

using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliDemo){};

namespace {

/// The two figures of a summary row ("label   46.2 %   2.5 %"); -1 where one is missing.
std::pair<double, double> SummaryRow(const Run& r, const std::string& label) {
  const size_t at = r.output.find(label);
  if (at == std::string::npos) return {-1, -1};
  double nominal = -1, calibrated = -1;
  char unit[8];
  std::sscanf(r.output.c_str() + at + label.size(), " %lf %7s %lf", &nominal, unit, &calibrated);
  return {nominal, calibrated};
}

}  // namespace

TEST(CliDemo, CalibratedFingersFollowTheirTargetsWhereNominalOnesShowTheirLoops) {
  // ./run demo's main job end to end: the stimuli on the nominal curves, the pneumatic fingers
  // calibrated on simulated rigs (api), the stimuli again.
  const std::string chart = OwnTempPath("demo.svg");
  const Run r = Palpa("demo --out " + chart);
  std::ifstream svg(chart);
  const bool plotted = svg.good();
  std::remove(chart.c_str());
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(plotted);
  CHECK(Has(r, "pass 2"));
  // Its millimetres say whose they are: Table 5-4's film, without the top layer.
  CHECK(Has(r, "Deformation is the bare film's"));
  CHECK(Has(r, "without the top silicone layer"));
  CHECK_TEXT(Has(r, "calibrated, api(8)"), r.output.c_str());
  const auto worst = SummaryRow(r, "pneumatic fingers: largest |error| / target");
  const auto gap = SummaryRow(r, "level 1 from above minus from below");
  // Nominal: the film's loop (0.18 against 0.36 mm at one target); calibrated: a few percent.
  CHECK_TEXT(worst.first > 30, r.output.c_str());
  CHECK_TEXT(worst.second >= 0 && worst.second < 10, r.output.c_str());
  CHECK_TEXT(gap.first > 100, r.output.c_str());
  CHECK_TEXT(std::fabs(gap.second) < 40, r.output.c_str());
}
