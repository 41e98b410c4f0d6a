// Scene files: every tissue source, layout kind and mapping written and read back the same; the
// shipped example read, its tissue made and rendered; relative paths from the file's directory;
// bad fields named.
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/scene_file.h"

#include "CppUTest/TestHarness.h"
#include "scene_examples.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

nlohmann::json Example() {
  std::ifstream in(palpa::testing::kThreeCubeScene);
  return nlohmann::json::parse(in);
}

std::string RefusedScene(const nlohmann::json& j) {
  const auto s = ph::ParseScene(j.dump());
  CHECK_TEXT(!s.ok(), "accepted");
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)s.status);
  return s.message;
}

/// Written, read, written again: the same text.
void RoundTrips(const ph::SceneSpec& spec) {
  const auto text = ph::SerializeScene(spec);
  CHECK_TEXT(text.ok(), text.message.c_str());
  const auto back = ph::ParseScene(text.value);
  CHECK_TEXT(back.ok(), back.message.c_str());
  STRCMP_EQUAL(text.value.c_str(), ph::SerializeScene(back.value).value.c_str());
}

}  // namespace

TEST_GROUP(SceneFile){};

TEST(SceneFile, TheExampleIsTheThesisTriangleOnTheThreeCubePhantom) {
  const auto s = ph::LoadScene(palpa::testing::kThreeCubeScene);
  CHECK_TEXT(s.ok(), s.message.c_str());
  CHECK(s.value.source == ph::TissueSource::kPreset);
  STRCMP_EQUAL("thesis-three-cube", s.value.preset.c_str());
  const ph::FingerLayout layout = ph::MakeLayout(s.value.layout);
  LONGS_EQUAL(3, layout.fingers.size());
  LONGS_EQUAL(3, s.value.board_fingers.size());
  CHECK(s.value.rule.pneumatic == ph::PneumaticMapping::kFingertipStress);
  const auto tissue = ph::LoadSceneTissue(s.value);
  CHECK_TEXT(tissue.ok(), tissue.message.c_str());
  std::vector<ph::RenderFinger> fingers;
  for (uint8_t f : s.value.board_fingers)
    fingers.push_back(
        {f, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, f, pp::kNoLine}, {}});
  const auto r = ph::SceneRenderer::Make(tissue.value, layout, s.value.rule, fingers);
  CHECK_TEXT(r.ok(), r.message.c_str());
  CHECK(r.value.Render({0, 60, 12, 1})[0].mapped.target > 0);
  RoundTrips(s.value);
}

TEST(SceneFile, EveryTissueSourceLayoutAndMappingRoundTrips) {
  ph::SceneSpec s = ph::ParseScene(Example().dump()).value;
  s.source = ph::TissueSource::kPhantom;
  s.phantom = ph::ThreeCubePhantom();
  s.layout = {"row", 12.5, 4, {}, 30, 6};
  s.board_fingers = {3, 2, 1, 0};
  s.rule.pneumatic = ph::PneumaticMapping::kDeformation;
  s.rule.deformation_lo_mm = 0.25;
  s.rule.deformation_hi_mm = 2.5;
  s.rule.value_lo = 10;
  s.rule.value_hi = 40;
  RoundTrips(s);
  s.source = ph::TissueSource::kForceMatrices;
  s.scan = {"scan", 0.7658, 2, {{"d2.csv", 2}, {"d3.csv", 3}}};
  s.layout = {"custom", 0, 0, {{0, 0}, {-7.5, 1.0 / 3}}, 0, 0};
  s.board_fingers = {0, 1};
  s.rule = {};
  s.rule.pneumatic = ph::PneumaticMapping::kLevel;
  RoundTrips(s);
  s.source = ph::TissueSource::kImage;
  s.image_file = "maps/liver.pgm";
  s.image_scale = {s.name, "kPa", 0.25, 3.5, 48.125};
  RoundTrips(s);
  s.source = ph::TissueSource::kFile;
  s.tissue_file = "maps/liver.json";
  s.layout = {"jamming-pair", 20, 0, {}, 0, 8};
  RoundTrips(s);
  // A spec that could not be read back is refused when written.
  s.board_fingers = {0};
  CHECK_STARTS(ph::SerializeScene(s).message,
               "the scene would not read back: fingers: has 1 entries, needs 2");
}

TEST(SceneFile, RelativeTissuePathsStartAtTheScenesDirectory) {
  char pattern[] = "/tmp/palpa-scene-file-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  nlohmann::json j = Example();
  j["tissue"] = {{"force_matrices",
                  {{"along_line_pitch_mm", 1},
                   {"line_pitch_mm", 2},
                   {"files", {{{"path", "d2.csv"}, {"depth_mm", 2}}}}}}};
  std::ofstream(dir + "/scene.json") << j.dump();
  std::ofstream(dir + "/d2.csv") << "1,2\n3,4\n";
  const auto s = ph::LoadScene(dir + "/scene.json");
  CHECK_TEXT(s.ok(), s.message.c_str());
  STRCMP_EQUAL((dir + "/d2.csv").c_str(), s.value.scan.files[0].path.c_str());
  const auto tissue = ph::LoadSceneTissue(s.value);
  CHECK_TEXT(tissue.ok(), tissue.message.c_str());
  DOUBLES_EQUAL(2, tissue.value.pitch_y_mm, 0);
  j["tissue"] = {{"image",
                  {{"path", "map.pgm"},
                   {"mm_per_pixel", 2},
                   {"unit", "kPa"},
                   {"value_at_black", 10},
                   {"value_at_white", 20}}}};
  std::ofstream(dir + "/scene.json") << j.dump();
  std::ofstream(dir + "/map.pgm") << "P2 2 2 1\n0 1\n1 0\n";
  const auto image = ph::LoadScene(dir + "/scene.json");
  CHECK_TEXT(image.ok(), image.message.c_str());
  const auto from_image = ph::LoadSceneTissue(image.value);
  CHECK_TEXT(from_image.ok(), from_image.message.c_str());
  DOUBLES_EQUAL(2, from_image.value.pitch_x_mm, 0);
  DOUBLES_EQUAL(20, from_image.value.At(1, 1), 0);
  std::ofstream(dir + "/scene.json") << "{\"schema\": 1}";
  CHECK_STARTS(ph::LoadScene(dir + "/scene.json").message, dir + "/scene.json: schema: must be");
  CHECK(std::system(("rm -rf " + dir).c_str()) == 0);
}

TEST(SceneFile, EveryBadFieldIsNamed) {
  auto broken = [](auto edit) {
    nlohmann::json j = Example();
    edit(j);
    return RefusedScene(j);
  };
  CHECK_STARTS(broken([](auto& j) { j["schema"] = "palpa-tissue"; }), "schema: must be");
  CHECK_STARTS(broken([](auto& j) {
                 j["tissue"] = {{"preset", "x"}, {"file", "y"}};
               }),
               "tissue: must hold exactly one of");
  CHECK_STARTS(broken([](auto& j) {
                 j["tissue"] = {{"preset", "liver"}};
               }),
               "tissue.preset: \"liver\" is not a preset");
  CHECK_STARTS(broken([](auto& j) { j["layout"]["kind"] = "circle"; }),
               "layout.kind: \"circle\" is not one of");
  CHECK_STARTS(broken([](auto& j) { j["layout"]["contact_diameter_mm"] = 200; }),
               "layout.contact_diameter_mm: 200 is outside");
  CHECK_STARTS(broken([](auto& j) { j["fingers"] = {0, 1}; }), "fingers: has 2 entries, needs 3");
  CHECK_STARTS(broken([](auto& j) { j["fingers"][2] = 8; }), "fingers[2]: must be a board finger");
  CHECK_STARTS(broken([](auto& j) { j["fingers"][2] = 0; }),
               "fingers[2]: board finger 0 is fingers[0] already");
  CHECK_STARTS(broken([](auto& j) { j["rule"]["contrast"] = 0; }), "rule.contrast: 0 is outside");
  CHECK_STARTS(broken([](auto& j) {
                 j["rule"]["pneumatic"]["range_kpa"] = {5.91, 40};
               }),
               "rule: stress 5.91 … 40 kPa is not a range");
  CHECK_STARTS(broken([](auto& j) {
                 j["rule"]["pneumatic"]["range_mm"] = {0, 1};
               }),
               "rule.pneumatic.range_mm: only the deformation mapping has one");
  CHECK_STARTS(broken([](auto& j) {
                 j["rule"]["value_range"] = {3, 3};
               }),
               "rule.value_range: must rise");
  nlohmann::json phantom = {
      {"name", "p"},      {"unit", "kPa"},   {"size_mm", {50, 20, 10}},
      {"background", 10}, {"pitch_mm", 0.5}, {"inclusions", nlohmann::json::array()}};
  phantom["inclusions"].push_back({{"name", "a"},
                                   {"centre_mm", {25, 10}},
                                   {"size_mm", {5, 5, 5}},
                                   {"depth_mm", 6},
                                   {"stiffness", 100}});
  CHECK_STARTS(broken([&](auto& j) {
                 j["tissue"] = {{"phantom", phantom}};
               }),
               "tissue.phantom.inclusions[0].depth_mm: 6 + thickness 5 mm does not fit");
  phantom["inclusions"][0]["size_mm"][2] = -1;
  CHECK_STARTS(broken([&](auto& j) {
                 j["tissue"] = {{"phantom", phantom}};
               }),
               "tissue.phantom.inclusions[0].size_mm[2]: must be a number of mm above 0");
}
