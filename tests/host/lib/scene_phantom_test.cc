// Generated phantoms against their specification (the three-cube preset's cubes where they were
// put, their series-column stiffness, the thesis's order of how well each was found), bad specs
// named by field, and finger layouts sampling what lies under each finger.
#include <cmath>
#include <string>

#include "palpa/host/scene_fingers.h"
#include "palpa/host/scene_phantom.h"
#include "palpa/host/scene_svg.h"

#include "CppUTest/TestHarness.h"
#include "scene_examples.h"
#include "text_checks.h"

namespace ph = palpa::host;

namespace {

double Point(const ph::TissueMap& m, double x, double y) {
  double v = NAN;
  CHECK(ph::InterpolateGrid(m, m.values, x, y, &v));
  return v;
}

/// Series column: H / ((H − t)/Eb + t/Ei).
double Column(double h, double t, double eb, double ei) { return h / ((h - t) / eb + t / ei); }

std::string RefusedPhantom(const ph::PhantomSpec& s) {
  const auto m = ph::GeneratePhantom(s);
  CHECK_TEXT(!m.ok(), "accepted");
  return m.message;
}

}  // namespace

TEST_GROUP(ScenePhantom){};

TEST(ScenePhantom, TheThreeCubePresetMatchesItsSpecification) {
  const ph::PhantomSpec spec = ph::ThreeCubePhantom();
  const ph::TissueMap m = palpa::testing::ThreeCubeMap();
  STRCMP_EQUAL("kPa", m.unit.c_str());
  LONGS_EQUAL(241, m.nx);  // 120 mm at 0.5 mm
  LONGS_EQUAL(61, m.ny);
  DOUBLES_EQUAL(120, m.extent_x_mm(), 1e-9);
  DOUBLES_EQUAL(30, m.extent_y_mm(), 1e-9);
  LONGS_EQUAL(3, spec.inclusions.size());
  const double sides[] = {4, 12, 8};
  for (size_t k = 0; k < 3; ++k) {
    const ph::Inclusion& c = spec.inclusions[k];
    DOUBLES_EQUAL(sides[k], c.thickness_mm, 0);  // cubes: thickness is every side
    DOUBLES_EQUAL(sides[k], c.size_x_mm, 0);
    // Over the cube: the column with the cube in it; just outside its footprint: the block.
    DOUBLES_EQUAL(Column(20, sides[k], 14.7, 1590), Point(m, c.x_mm, c.y_mm), 1e-9);
    DOUBLES_EQUAL(Column(20, sides[k], 14.7, 1590), Point(m, c.x_mm + sides[k] / 2, c.y_mm), 1e-9);
    DOUBLES_EQUAL(14.7, Point(m, c.x_mm + sides[k] / 2 + 0.5, c.y_mm), 1e-9);
    DOUBLES_EQUAL(14.7, Point(m, c.x_mm, c.y_mm + sides[k] / 2 + 0.5), 1e-9);
  }
  DOUBLES_EQUAL(14.7, m.Range().first, 1e-12);
  DOUBLES_EQUAL(Column(20, 12, 14.7, 1590), m.Range().second, 1e-9);
  // The thesis found B (12 mm) always, C (8 mm) mostly, A (4 mm) least: the map's contrast
  // ranks them the same way.
  CHECK(Point(m, 60, 15) > Point(m, 90, 15));
  CHECK(Point(m, 90, 15) > Point(m, 30, 15));
  CHECK(Point(m, 30, 15) > 14.7);
}

TEST(ScenePhantom, DepthOnlyHasToFitAndStackedInclusionsAddTheirCompliance) {
  ph::PhantomSpec s{"two", "", "kPa", 20, 10, 10, 10, 1, {}};
  s.inclusions = {{"top", 10, 5, 4, 4, 2, 1, 100}, {"under", 10, 5, 4, 4, 3, 5, 50}};
  const auto m = ph::GeneratePhantom(s);
  CHECK_TEXT(m.ok(), m.message.c_str());
  DOUBLES_EQUAL(10 / (5.0 / 10 + 2.0 / 100 + 3.0 / 50), Point(m.value, 10, 5), 1e-9);
  s.inclusions[1].depth_mm = 2;  // now it shares volume with the top one
  CHECK_STARTS(RefusedPhantom(s), "phantom two: inclusions[1]: overlaps inclusions[0]");
}

TEST(ScenePhantom, EveryBadFieldIsNamed) {
  auto with = [](auto edit) {
    ph::PhantomSpec s = ph::ThreeCubePhantom();
    edit(s);
    return RefusedPhantom(s);
  };
  const std::string p = "phantom thesis-three-cube: ";
  CHECK_STARTS(with([](auto& s) { s.size_x_mm = 0; }), p + "size_x_mm: 0 is not in (0, 10000]");
  CHECK_STARTS(with([](auto& s) { s.height_mm = NAN; }), p + "height_mm: nan");
  CHECK_STARTS(with([](auto& s) { s.background = -1; }), p + "background: -1 is not above 0");
  CHECK_STARTS(with([](auto& s) { s.pitch_mm = 0.01; }),
               p + "pitch_mm: 0.01 mm over 120 mm makes 12001 points on a side");
  CHECK_STARTS(with([](auto& s) { s.inclusions[1].x_mm = 115; }),
               p + "inclusions[1].x_mm: 115 puts it outside the block (0 … 120 mm)");
  CHECK_STARTS(with([](auto& s) { s.inclusions[2].y_mm = -1; }), p + "inclusions[2].y_mm: -1");
  CHECK_STARTS(with([](auto& s) { s.inclusions[1].depth_mm = 9; }),
               p + "inclusions[1].depth_mm: 9 + thickness 12 mm does not fit in the block's "
                   "height of 20 mm");
  CHECK_STARTS(with([](auto& s) { s.inclusions[0].stiffness = 0; }),
               p + "inclusions[0].stiffness: 0 is not above 0");
  CHECK_STARTS(with([](auto& s) { s.inclusions[0].thickness_mm = INFINITY; }),
               p + "inclusions[0].thickness_mm: inf");
  CHECK_STARTS(with([](auto& s) { s.name = ""; }), "phantom (unnamed): a phantom needs a name");
}

TEST_GROUP(SceneFingers){};

TEST(SceneFingers, TheThesisTriangleFollowsTheInputWithItsRightAngle) {
  const ph::FingerLayout t = ph::RightTriangleLayout(15, 4);
  CHECK(ph::CheckLayout(t).ok());
  LONGS_EQUAL(3, t.fingers.size());
  DOUBLES_EQUAL(0, t.fingers[0].dx_mm, 0);
  DOUBLES_EQUAL(0, t.fingers[0].dy_mm, 0);
  // The legs meet at a right angle at finger 0 and are `spacing` long.
  const auto& a = t.fingers[1];
  const auto& b = t.fingers[2];
  DOUBLES_EQUAL(0, a.dx_mm * b.dx_mm + a.dy_mm * b.dy_mm, 1e-12);
  DOUBLES_EQUAL(15, std::hypot(a.dx_mm, a.dy_mm), 1e-12);
  DOUBLES_EQUAL(15, std::hypot(b.dx_mm, b.dy_mm), 1e-12);
  const ph::FingerLayout r = ph::Rotated(t, 90);
  DOUBLES_EQUAL(0, r.fingers[1].dx_mm, 1e-12);
  DOUBLES_EQUAL(15, r.fingers[1].dy_mm, 1e-12);
  DOUBLES_EQUAL(-15, r.fingers[2].dx_mm, 1e-12);
}

TEST(SceneFingers, RowsAreCentredAndEachFingerFeelsWhatIsUnderIt) {
  const ph::FingerLayout row = ph::RowLayout(4, 10, 0);
  DOUBLES_EQUAL(-15, row.fingers[0].dx_mm, 1e-12);
  DOUBLES_EQUAL(15, row.fingers[3].dx_mm, 1e-12);
  const ph::FingerLayout pair = ph::JammingPairLayout(20, 6);
  LONGS_EQUAL(2, pair.fingers.size());
  DOUBLES_EQUAL(-10, pair.fingers[0].dx_mm, 1e-12);
  // Over the three-cube phantom: the pair straddling cube B, each finger on the block.
  const ph::TissueMap m = palpa::testing::ThreeCubeMap();
  auto under = ph::SampleFingers(m, pair, 60, 15);
  DOUBLES_EQUAL(14.7, under[0].value, 1e-9);
  DOUBLES_EQUAL(14.7, under[1].value, 1e-9);
  // Moved so finger 1 sits on B's centre: it feels B (its disc lies within B), finger 0 not.
  under = ph::SampleFingers(m, pair, 50, 15);
  DOUBLES_EQUAL(Column(20, 12, 14.7, 1590), under[1].value, 1e-9);
  DOUBLES_EQUAL(14.7, under[0].value, 1e-9);
  // Finger 0 off the tissue's left edge: nothing under it.
  under = ph::SampleFingers(m, pair, 2, 15);
  DOUBLES_EQUAL(0, under[0].coverage, 0);
  DOUBLES_EQUAL(1, under[1].coverage, 1e-12);
}

TEST(SceneFingers, BadLayoutsAreNamed) {
  ph::FingerLayout l = ph::RowLayout(9, 10, 4);
  CHECK_STARTS(ph::CheckLayout(l).message, "fingers: 9 of them, a layout has 1 … 8");
  l = ph::RightTriangleLayout(NAN, 4);
  CHECK_STARTS(ph::CheckLayout(l).message, "fingers[1].dx_mm: nan is not within ±500 mm");
  l = ph::RightTriangleLayout(15, -1);
  CHECK_STARTS(ph::CheckLayout(l).message, "contact_diameter_mm: -1 is not within 0 … 100 mm");
  l.fingers.clear();
  CHECK_STARTS(ph::CheckLayout(l).message, "fingers: 0 of them");
}

TEST_GROUP(SceneSvg){};

TEST(SceneSvg, TheMapIsDrawnInColourWithEachFingersDiscAndThePath) {
  const ph::TissueMap m = palpa::testing::ThreeCubeMap();
  const std::string svg =
      ph::SceneSvg(m, ph::RightTriangleLayout(15, 4), 60, 12, {{0, 15}, {120, 15}}, "B < C & A");
  CHECK(svg.rfind("<svg ", 0) == 0);
  CHECK(svg.find("B &lt; C &amp; A") != std::string::npos);
  size_t circles = 0, cells = 0;
  for (size_t at = svg.find("<circle"); at != std::string::npos; at = svg.find("<circle", at + 1))
    ++circles;
  for (size_t at = svg.find("<rect"); at != std::string::npos; at = svg.find("<rect", at + 1))
    ++cells;
  LONGS_EQUAL(3, circles);
  // 241 points along x are more than 240: every second one (121), all 61 along y; the outline;
  // the scale bar.
  LONGS_EQUAL(121 * 61 + 1 + 100, cells);
  CHECK(svg.find("fill='#ff0000'") != std::string::npos);  // cube B, the largest value
  CHECK(svg.find("fill='#0000ff'") != std::string::npos);  // the block, the smallest
  CHECK(svg.find("<polyline") != std::string::npos);
  CHECK(svg.find("14.7 … 36.2") != std::string::npos);
  // A map finer than 240 points a side is sampled, not drawn point by point.
  ph::PhantomSpec fine = ph::ThreeCubePhantom();
  fine.pitch_mm = 0.125;  // 961 × 241 points
  const std::string small =
      ph::SceneSvg(ph::GeneratePhantom(fine).value, ph::RowLayout(1, 1, 0), 0, 0, {}, "fine");
  cells = 0;
  for (size_t at = small.find("<rect"); at != std::string::npos; at = small.find("<rect", at + 1))
    ++cells;
  CHECK(cells <= 240 * 240 + 101);
}
