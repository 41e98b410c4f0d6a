// Scene tissues: interpolation and contact discs on known maps, the JSON grid round-tripped, CSV
// force matrices read into Hooke's-law stiffness, and bad files of every kind refused by name.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/scene_files.h"
#include "palpa/host/scene_tissue.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace ph = palpa::host;

namespace {

/// A 3 × 2 map at a 2 mm × 1 mm pitch whose value is x + 10·y: bilinear interpolation is exact.
ph::TissueMap Ramp() {
  ph::TissueMap m;
  m.name = "ramp";
  m.unit = "kPa";
  m.pitch_x_mm = 2;
  m.pitch_y_mm = 1;
  m.nx = 3;
  m.ny = 2;
  m.values = {0, 2, 4, 10, 12, 14};
  return m;
}

std::string RefusedTissue(const std::string& text) {
  const auto m = ph::ParseTissue(text);
  CHECK_TEXT(!m.ok(), "accepted");
  LONGS_EQUAL((int)palpa::protocol::Status::kInvalidArgument, (int)m.status);
  return m.message;
}

nlohmann::json ValidDoc() {
  return nlohmann::json::parse(R"({"schema": "palpa-tissue", "schema_version": 1, "name": "t",
    "unit": "kPa", "pitch_mm": [2, 1], "extent_mm": [4, 1], "values": [[0, 2, 4], [10, 12, 14]],
    "depths": [{"depth_mm": 2, "force_n": [[1, 1, 1], [2, 2, 2]]},
               {"depth_mm": 4, "force_n": [[2, 2, 2], [4, 4, 4]]}]})");
}

}  // namespace

TEST_GROUP(SceneTissue){};

TEST(SceneTissue, BilinearInterpolationIsExactOnAPlaneAndRefusesOutside) {
  const ph::TissueMap m = Ramp();
  CHECK(ph::CheckTissue(m).ok());
  double v = -1;
  CHECK(ph::InterpolateGrid(m, m.values, 3, 0.5, &v));
  DOUBLES_EQUAL(3 + 5, v, 1e-12);
  CHECK(ph::InterpolateGrid(m, m.values, 4, 1, &v));  // the far corner is on the map
  DOUBLES_EQUAL(14, v, 1e-12);
  CHECK(!ph::InterpolateGrid(m, m.values, 4.01, 0, &v));
  CHECK(!ph::InterpolateGrid(m, m.values, -0.01, 0, &v));
  CHECK(!ph::InterpolateGrid(m, m.values, NAN, 0, &v));
}

TEST(SceneTissue, ADiscAveragesAPlaneToItsCentreAndCountsWhatIsOffTheMap) {
  ph::TissueMap m = Ramp();
  const ph::ContactSample inside = ph::SampleDisc(m, 2, 0.5, 0.9);
  DOUBLES_EQUAL(1, inside.coverage, 1e-12);
  DOUBLES_EQUAL(2 + 5, inside.value, 1e-9);  // a plane's mean over a disc is its centre value
  // Centred on the left edge: half the disc is off the tissue.
  const ph::ContactSample edge = ph::SampleDisc(m, 0, 0.5, 0.8);
  DOUBLES_EQUAL(0.5, edge.coverage, 0.02);
  CHECK(edge.value > 5);  // only the part on the map counts
  const ph::ContactSample off = ph::SampleDisc(m, 50, 50, 2);
  DOUBLES_EQUAL(0, off.coverage, 0);
  // A kink: flat up to x = 10, then rising 0.1 per mm. Centred on the kink, the disc's mean is
  // 0.1 times the mean of max(0, x − 10) over it: 0.1 · ½ · 4r/3π = 0.0424 for r = 2 mm.
  m.values = {0, 0, 1, 0, 0, 1};
  m.pitch_x_mm = m.pitch_y_mm = 10;
  DOUBLES_EQUAL(0.1 * 0.5 * 4 * 2 / (3 * M_PI), ph::SampleDisc(m, 10, 5, 4).value, 0.002);
  DOUBLES_EQUAL(0.5, ph::SampleDisc(m, 15, 5, 4).value, 1e-9);  // wholly on the slope
  DOUBLES_EQUAL(0, ph::SampleDisc(m, 5, 5, 4).value, 0);        // wholly on the flat
}

TEST(SceneTissue, TheJsonGridRoundTripsEveryValue) {
  ph::TissueMap m = Ramp();
  m.values[4] = 0.1 + 0.2;  // not a short decimal
  m.layers = {{2, {1, 1, 1, 2, 2, 2}}, {4.5, {2, 2, 2, 4, 4, 4.000000000000001}}};
  const auto text = ph::SerializeTissue(m);
  CHECK_TEXT(text.ok(), text.message.c_str());
  const auto back = ph::ParseTissue(text.value);
  CHECK_TEXT(back.ok(), back.message.c_str());
  CHECK(back.value.values == m.values);
  LONGS_EQUAL(3, back.value.nx);
  DOUBLES_EQUAL(2, back.value.pitch_x_mm, 0);
  DOUBLES_EQUAL(1, back.value.pitch_y_mm, 0);
  LONGS_EQUAL(2, back.value.layers.size());
  CHECK(back.value.layers[1].force_n == m.layers[1].force_n);
  STRCMP_EQUAL(text.value.c_str(), ph::SerializeTissue(back.value).value.c_str());
  CHECK(ph::ParseTissue(ValidDoc().dump()).ok());
}

TEST(SceneTissue, EveryBadFieldIsNamedWithWhatWasExpected) {
  auto broken = [](auto edit) {
    nlohmann::json j = ValidDoc();
    edit(j);
    return RefusedTissue(j.dump());
  };
  CHECK_STARTS(broken([](auto& j) { j["schema"] = "palpa-stimuli"; }), "schema: must be");
  CHECK_STARTS(broken([](auto& j) { j["schema_version"] = 2; }), "schema_version: 2 is outside");
  CHECK_STARTS(broken([](auto& j) { j["colour"] = 1; }), "colour: unknown field");
  CHECK_STARTS(broken([](auto& j) { j.erase("unit"); }), "unit: missing");
  CHECK_STARTS(broken([](auto& j) { j["pitch_mm"] = -1; }), "pitch_mm: -1 is outside");
  CHECK_STARTS(broken([](auto& j) { j["pitch_mm"] = {2, 0}; }), "pitch_mm[1]: must be");
  CHECK_STARTS(broken([](auto& j) {
                 j["extent_mm"] = {4, 2};
               }),
               "extent_mm[1]: 2 mm is not (points − 1) · pitch = 1 · 1 = 1 mm");
  CHECK_STARTS(broken([](auto& j) { j["values"][1][2] = "stiff"; }),
               "values[1][2]: must be a number");
  CHECK_STARTS(broken([](auto& j) { j["values"][1].erase(2); }),
               "values[1]: has 2 values, needs 3 (as row 0 of values)");
  CHECK_STARTS(broken([](auto& j) { j["values"] = {{1, 2, 3}}; }), "values: has 1 rows, needs 2");
  CHECK_STARTS(broken([](auto& j) { j["values"][0] = 7; }), "values[0]: must be an array");
  CHECK_STARTS(broken([](auto& j) { j["depths"][1]["depth_mm"] = 2; }),
               "depths[1].depth_mm: 2 is not deeper than the layer before (2)");
  CHECK_STARTS(broken([](auto& j) {
                 j["depths"][0]["force_n"].push_back({1, 1, 1});
               }),
               "depths[0].force_n: has 3 rows, needs 2");
  CHECK_STARTS(broken([](auto& j) { j["depths"][0]["force_n"][0][1] = nullptr; }),
               "depths[0].force_n[0][1]: must be a number");
  CHECK_STARTS(RefusedTissue("{\"schema\": \"palpa-tissue\", \"values\": [[1e400"),
               "values[0][0]: the number");
  CHECK_STARTS(RefusedTissue("[1, 2"), "[2]: not valid JSON");
}

TEST_GROUP(SceneForceMatrices) {
  std::string dir;
  void setup() override {
    char pattern[] = "/tmp/palpa-scene-XXXXXX";
    dir = mkdtemp(pattern);
  }
  void teardown() override { CHECK(std::system(("rm -rf " + dir).c_str()) == 0); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string Refused(const ph::ForceMatrixScan& scan) {
    const auto m = ph::LoadForceMatrices(scan);
    CHECK_TEXT(!m.ok(), "accepted");
    return m.message;
  }
};

TEST(SceneForceMatrices, DepthsBecomeLayersAndStiffnessIsTheirSlopeThroughTheOrigin) {
  // Point 0 is linear (0.5 N/mm); point 1 is not: its least-squares slope is Σfd / Σd².
  const std::string a = Write("d2.csv", "# force at 2 mm, N\n1.0, 2.0\n3.0,4.0\r\n\n1,1\n");
  const std::string b = Write("d4.csv", "2.0,3.0\n6,8\n2,2\n");
  const auto m = ph::LoadForceMatrices({"scan", 0.76, 2, {{a, 2}, {b, 4}}});
  CHECK_TEXT(m.ok(), m.message.c_str());
  LONGS_EQUAL(2, m.value.nx);
  LONGS_EQUAL(3, m.value.ny);
  STRCMP_EQUAL("N/mm", m.value.unit.c_str());
  DOUBLES_EQUAL(0.76, m.value.pitch_x_mm, 0);
  DOUBLES_EQUAL(2, m.value.pitch_y_mm, 0);
  LONGS_EQUAL(2, m.value.layers.size());
  DOUBLES_EQUAL(4, m.value.layers[1].depth_mm, 0);
  DOUBLES_EQUAL(0.5, m.value.At(0, 0), 1e-12);
  DOUBLES_EQUAL((2.0 * 2 + 3.0 * 4) / 20, m.value.At(1, 0), 1e-12);
  DOUBLES_EQUAL(2, m.value.layers[1].force_n[2 * 2 + 1], 0);  // point (1, 2)
}

TEST(SceneForceMatrices, BadMatricesAreNamedByFileLineAndValue) {
  const std::string good = Write("good.csv", "1,2,3\n4,5,6\n");
  auto one = [&](const std::string& text) {
    return Refused({"s", 1, 2, {{Write("bad.csv", text), 2}}});
  };
  CHECK_STARTS(one("1,2,3\n4,x5,6\n"), dir + "/bad.csv: line 2, value 2: \"x5\" is not a number");
  CHECK_STARTS(one("1,2,3\n4,,6\n"), dir + "/bad.csv: line 2, value 2: \"\" is not a number");
  CHECK_STARTS(one("# header\n1,2,3\n4,5\n"),
               dir + "/bad.csv: line 3: 2 values where line 2 has 3");
  CHECK_STARTS(one("1,2,1e999\n"), dir + "/bad.csv: line 1, value 3: \"1e999\"");
  CHECK_STARTS(one("1,2,nan\n4,5,6\n"), dir + "/bad.csv: line 1, value 3: \"nan\"");
  CHECK_STARTS(one("1,2,3\n"), dir + "/bad.csv: a force matrix needs at least 2 scan lines");
  CHECK_STARTS(one(""), dir + "/bad.csv: a force matrix needs");
  CHECK_STARTS(Refused({"s", 1, 2, {{good, 2}, {Write("small.csv", "1,2\n3,4\n"), 3}}}),
               dir + "/small.csv: 2 lines of 2 values, where " + good + " has 2 of 3");
  CHECK_STARTS(Refused({"s", 1, 2, {{good, 3}, {good, 3}}}), good + ": depth 3 mm: depths rise");
  CHECK_STARTS(Refused({"s", 1, 2, {{good, NAN}}}), good + ": depth nan mm");
  CHECK_STARTS(Refused({"s", 1, 2, {{dir + "/none.csv", 2}}}), dir + "/none.csv: cannot be read");
  CHECK_STARTS(Refused({"s", 0, 2, {{good, 2}}}), "force matrices " + good + " …: pitch 0 mm");
  CHECK_STARTS(Refused({"s", 1, 2, {}}), "a scan has 1 … 32 force matrices");
  // A FIFO is refused, not waited on; a file past the cap is refused before it is read.
  const std::string fifo = dir + "/fifo.csv";
  CHECK(mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_STARTS(Refused({"s", 1, 2, {{fifo, 2}}}), fifo + ": not a regular file");
  const std::string big = dir + "/big.csv";
  CHECK(truncate(Write("big.csv", "").c_str(), ph::kForceMatrixLimits.max_bytes + 1) == 0);
  CHECK_STARTS(Refused({"s", 1, 2, {{big, 2}}}), big + ": larger than the 16 MiB limit");
  // A line longer than a map may be is refused at the limit, not read on.
  std::string wide;
  for (size_t k = 0; k <= ph::kMaxTissuePoints; ++k) wide += "1,";
  CHECK_STARTS(one(wide + "1\n"), dir + "/bad.csv: line 1: more than 1024 values");
}

TEST(SceneForceMatrices, TissueFilesAreReadWithinTheirCap) {
  const std::string path = Write("t.json", ValidDoc().dump());
  CHECK(ph::LoadTissue(path).ok());
  CHECK(truncate(path.c_str(), ph::kTissueFileLimits.max_bytes + 1) == 0);
  CHECK_STARTS(ph::LoadTissue(path).message, path + ": larger than the 32 MiB limit for a tissue");
  CHECK_STARTS(ph::LoadTissue(Write("bad.json", "{}")).message, dir + "/bad.json: schema: missing");
}
