// The rendering rule: on the three-cube phantom, each finger's target in its own unit through
// its curve (deformation, levels, the fingertip-stress line; N/mm for jamming fingers), contact
// and release, force selecting depth on a tissue with depth, and bad scenes refused by name.
#include <cmath>
#include <string>

#include "palpa/host/scene_phantom.h"
#include "palpa/host/scene_render.h"

#include "CppUTest/TestHarness.h"
#include "scene_examples.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

ph::RenderFinger Pneumatic(uint8_t board) {
  return {board, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, board, pp::kNoLine}, {}};
}

ph::RenderFinger Jamming(uint8_t board) {
  return {board, {pp::FingerKind::kJamming, pp::FingerMode::kTarget, board, 7}, {}};
}

ph::SceneRenderer Make(ph::TissueMap t, ph::FingerLayout l, ph::RenderRule rule,
                       std::vector<ph::RenderFinger> f) {
  auto r = ph::SceneRenderer::Make(std::move(t), std::move(l), rule, std::move(f));
  CHECK_TEXT(r.ok(), r.message.c_str());
  return r.value;
}

/// The triangle over the phantom: finger 1 15 mm to +x of finger 0 (the right angle), finger 2
/// 15 mm to +y.
ph::SceneRenderer Triangle(ph::RenderRule rule = {}) {
  return Make(palpa::testing::ThreeCubeMap(), ph::RightTriangleLayout(15, 4), rule,
              {Pneumatic(0), Pneumatic(1), Pneumatic(2)});
}

}  // namespace

TEST_GROUP(SceneRender){};

TEST(SceneRender, AFingerOnTheStiffestCubeGetsTheTopOfItsCurveAndTheBlockNothing) {
  const ph::SceneRenderer r = Triangle();
  // Finger 0 on cube B (the map's stiffest), finger 1 at x = 75 and finger 2 at y = 27 on the
  // block.
  const auto out = r.Render({0, 60, 12, 1.0});
  LONGS_EQUAL(3, out.size());
  CHECK(out[0].touching);
  DOUBLES_EQUAL(1, out[0].u, 1e-12);  // not at B's centre, but wholly on it
  CHECK(out[0].request.kind == ph::TargetKind::kDeformationMm);
  DOUBLES_EQUAL(ph::FingerCurves{}.max_deformation_mm, out[0].request.value, 1e-12);
  LONGS_EQUAL(4370, out[0].mapped.target);  // µm, the finger's nominal maximum
  DOUBLES_EQUAL(0, out[1].u, 1e-12);
  LONGS_EQUAL(0, out[1].mapped.target);
  DOUBLES_EQUAL(14.7, out[1].value, 1e-9);
  // The requests: one per finger, by board finger, for one Set (one stream frame).
  const auto requests = r.Requests(out);
  LONGS_EQUAL(3, requests.size());
  LONGS_EQUAL(2, requests[2].finger);
}

TEST(SceneRender, CubeCGetsItsShareOfTheRangeAndContrastStretchesIt) {
  const ph::TissueMap t = palpa::testing::ThreeCubeMap();
  const double lo = t.Range().first, hi = t.Range().second;
  double c = 0;
  CHECK(ph::InterpolateGrid(t, t.values, 90, 15, &c));
  const double linear = (c - lo) / (hi - lo);
  DOUBLES_EQUAL(linear, Triangle().Render({0, 90, 15, 1})[0].u, 1e-9);
  ph::RenderRule rule;
  rule.contrast = 2;
  const auto out = Triangle(rule).Render({0, 90, 15, 1});
  DOUBLES_EQUAL(linear * linear, out[0].u, 1e-9);
  DOUBLES_EQUAL(linear * linear * 4.370, out[0].request.value, 1e-9);
}

TEST(SceneRender, BelowTheContactForceOrOffTheTissueAFingerIsReleased) {
  const ph::SceneRenderer r = Triangle();
  for (const ph::FingerRender& f : r.Render({0, 60, 15, 0.04})) {
    CHECK(!f.touching);
    CHECK(f.request.kind == ph::TargetKind::kNormalized);
    LONGS_EQUAL(0, f.mapped.target);
  }
  for (const ph::FingerRender& f : r.Render({0, 60, 15, NAN})) CHECK(!f.touching);
  // The input at the far edge: finger 1 (15 mm to +x) is off the tissue; finger 2 is on it.
  const auto out = r.Render({0, 110, 5, 1});
  CHECK(out[0].touching);
  CHECK(!out[1].touching);
  DOUBLES_EQUAL(0, out[1].contact.coverage, 0);
  CHECK(out[2].touching);
  for (const ph::FingerRender& f : r.Render({0, NAN, 5, 1})) CHECK(!f.touching);
}

TEST(SceneRender, PneumaticLevelsAndTheFingertipStressLine) {
  ph::RenderRule rule;
  rule.pneumatic = ph::PneumaticMapping::kLevel;
  auto out = Triangle(rule).Render({0, 60, 12, 1});
  CHECK(out[0].request.kind == ph::TargetKind::kLevel);
  DOUBLES_EQUAL(2, out[0].request.value, 0);  // the top of 0 / 10 / 30 kPa
  DOUBLES_EQUAL(0, out[1].request.value, 0);
  CHECK(out[0].mapped.from_table);
  DOUBLES_EQUAL(30, out[0].mapped.table_kpa, 0);
  rule.pneumatic = ph::PneumaticMapping::kFingertipStress;
  out = Triangle(rule).Render({0, 60, 12, 1});
  // u = 1: the stress of 30 kPa on the line, back to 30 kPa, through Table 5-4's line.
  DOUBLES_EQUAL(0.0458 * 30 - 0.2098, out[0].request.value, 1e-9);
  rule.stress_hi_kpa = 50;  // past the line's 0 … 100 kPa
  CHECK_STARTS(
      ph::SceneRenderer::Make(palpa::testing::ThreeCubeMap(), ph::RightTriangleLayout(20, 4), rule,
                              {Pneumatic(0), Pneumatic(1), Pneumatic(2)})
          .message,
      "rule: stress 5.91 … 50 kPa is not a range within");
}

TEST(SceneRender, JammingFingersRenderNPerMmOverTheirOwnCurve) {
  std::vector<ph::RenderFinger> fingers = {Jamming(3), Jamming(4)};
  fingers[1].curves.stiffness_at_0 = 0.8;  // as a calibration would set it
  fingers[1].curves.stiffness_at_full_vacuum = 1.1;
  const ph::SceneRenderer r =
      Make(palpa::testing::ThreeCubeMap(), ph::JammingPairLayout(20, 4), {}, fingers);
  auto out = r.Render({0, 50, 15, 1});  // finger 1 on B, finger 0 on the block
  CHECK(out[1].request.kind == ph::TargetKind::kStiffnessNPerMm);
  DOUBLES_EQUAL(1.1, out[1].request.value, 1e-12);
  LONGS_EQUAL(1100, out[1].mapped.target);  // mN/mm
  DOUBLES_EQUAL(0.7, out[0].request.value, 1e-12);
  out = r.Render({0, 70, 15, 1});  // now finger 0 is on B
  DOUBLES_EQUAL(1.3, out[0].request.value, 1e-12);
  DOUBLES_EQUAL(0.8, out[1].request.value, 1e-12);
  LONGS_EQUAL(3, r.Requests(out)[0].finger);
}

TEST(SceneRender, OnATissueWithDepthTheForceSelectsTheDepthAndItsSlope) {
  ph::TissueMap t;
  t.name = "layered";
  t.unit = "N/mm";
  t.nx = t.ny = 2;
  t.pitch_x_mm = t.pitch_y_mm = 10;
  t.values = {0.5, 0.5, 0.5, 0.5};
  // Everywhere: 1 N at 2 mm, 3 N at 4 mm (softer above, stiffer below).
  t.layers = {{2, {1, 1, 1, 1}}, {4, {3, 3, 3, 3}}};
  const auto r = Make(t, ph::RowLayout(1, 10, 0), {}, {Pneumatic(0)});
  DOUBLES_EQUAL(0.5, r.value_lo(), 1e-12);
  DOUBLES_EQUAL(1, r.value_hi(), 1e-12);
  auto out = r.Render({0, 5, 5, 0.5});
  DOUBLES_EQUAL(1, out[0].depth_mm, 1e-12);
  DOUBLES_EQUAL(0.5, out[0].value, 1e-12);
  DOUBLES_EQUAL(0, out[0].u, 1e-12);
  out = r.Render({0, 5, 5, 2});
  DOUBLES_EQUAL(3, out[0].depth_mm, 1e-12);
  DOUBLES_EQUAL(1, out[0].u, 1e-12);
  const ph::DepthAtForce beyond = ph::PressDepth(t.layers, {1, 3}, 5);
  CHECK(beyond.beyond);
  DOUBLES_EQUAL(4, beyond.depth_mm, 0);
  // A scan that is not monotone: the first depth the force is met at.
  const std::vector<ph::ForceLayer> layers = {{2, {}}, {4, {}}, {6, {}}};
  const ph::DepthAtForce d = ph::PressDepth(layers, {1, 0.8, 2}, 1.5);
  DOUBLES_EQUAL(4 + 2 * 0.7 / 1.2, d.depth_mm, 1e-12);
  DOUBLES_EQUAL(0.6, d.slope_n_per_mm, 1e-12);
}

TEST(SceneRender, TheSameInputRendersTheSameTargets) {
  const ph::SceneRenderer r = Triangle();
  for (double x = 0; x <= 120; x += 0.37) {
    const auto a = r.Render({0, x, 12, 1.2}), b = r.Render({0, x, 12, 1.2});
    for (size_t k = 0; k < a.size(); ++k) {
      LONGS_EQUAL(a[k].mapped.target, b[k].mapped.target);
      CHECK(a[k].mapped.target >= 0 && a[k].mapped.target <= 4370);
    }
  }
}

TEST(SceneRender, BadScenesAreRefusedByName) {
  const auto tri = ph::RightTriangleLayout(15, 4);
  auto refused = [&](ph::TissueMap t, ph::FingerLayout l, ph::RenderRule rule,
                     std::vector<ph::RenderFinger> f) {
    const auto r = ph::SceneRenderer::Make(std::move(t), std::move(l), rule, std::move(f));
    CHECK_TEXT(!r.ok(), "accepted");
    return r.message;
  };
  const std::vector<ph::RenderFinger> three = {Pneumatic(0), Pneumatic(1), Pneumatic(2)};
  CHECK_STARTS(refused(palpa::testing::ThreeCubeMap(), tri, {}, {Pneumatic(0), Pneumatic(1)}),
               "fingers: 2 board fingers for the 3 places of layout right triangle, 15 mm");
  CHECK_STARTS(
      refused(palpa::testing::ThreeCubeMap(), tri, {}, {Pneumatic(0), Pneumatic(1), Pneumatic(0)}),
      "fingers[2]: board finger 0 drives another place");
  ph::TissueMap t = palpa::testing::ThreeCubeMap();
  t.values[7] = NAN;
  CHECK_STARTS(refused(t, tri, {}, three),
               "tissue thesis-three-cube: values: point (7, 0) is not a finite number");
  CHECK_STARTS(refused(palpa::testing::ThreeCubeMap(), ph::RowLayout(0, 1, 1), {}, {}),
               "layout row of 0, 1 mm: fingers");
  ph::RenderRule rule;
  rule.contrast = 0;
  CHECK_STARTS(refused(palpa::testing::ThreeCubeMap(), tri, rule, three),
               "rule: contrast 0 is not within (0, 10]");
  rule = {};
  rule.value_lo = 5;
  rule.value_hi = 1;
  CHECK_STARTS(refused(palpa::testing::ThreeCubeMap(), tri, rule, three),
               "rule: value_lo 5 and value_hi 1");
  rule = {};
  rule.contact_force_n = -1;
  CHECK_STARTS(refused(palpa::testing::ThreeCubeMap(), tri, rule, three),
               "rule: contact_force_n -1");
}
