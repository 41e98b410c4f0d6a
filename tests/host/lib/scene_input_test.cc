// Recorded trajectories: read line by line with every bad line named, and rendered across the
// three-cube phantom: the same targets every time, each cube's edge where its geometry puts it.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "palpa/host/scene_input.h"
#include "palpa/host/scene_phantom.h"
#include "palpa/host/scene_render.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

std::string RefusedTrajectory(const std::string& text) {
  const auto t = ph::ParseTrajectory(text, "pass.csv");
  CHECK_TEXT(!t.ok(), "accepted");
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)t.status);
  return t.message;
}

/// A straight pass along y = 15 mm at `speed` mm/s, 1 kHz, pressing 1 N.
std::string Pass(double speed) {
  std::string csv = "# straight pass\ntime_s, x_mm, y_mm, force_n\n";
  for (int k = 0; k * speed / 1000 <= 120; ++k) {
    char line[96];
    std::snprintf(line, sizeof(line), "%.3f,%.4f,15,1\n", k / 1000.0, k * speed / 1000);
    csv += line;
  }
  return csv;
}

}  // namespace

TEST_GROUP(SceneTrajectory){};

TEST(SceneTrajectory, ARecordedPassIsReadSampleBySample) {
  const auto t = ph::ParseTrajectory(
      "# from a pen\r\ntime_s,x_mm,y_mm,force_n\r\n0,1,2,0.5\r\n"
      "\r\n0.01, -3, 2.5 ,0\n",
      "pass.csv");
  CHECK_TEXT(t.ok(), t.message.c_str());
  LONGS_EQUAL(2, t.value.size());
  DOUBLES_EQUAL(0.01, t.value[1].time_s, 0);
  DOUBLES_EQUAL(-3, t.value[1].x_mm, 0);  // off the tissue is allowed
  DOUBLES_EQUAL(2.5, t.value[1].y_mm, 0);
  DOUBLES_EQUAL(0.5, t.value[0].force_n, 0);
}

TEST(SceneTrajectory, EveryBadLineIsNamed) {
  const std::string h = "time_s,x_mm,y_mm,force_n\n";
  CHECK_STARTS(RefusedTrajectory("t,x,y,f\n0,1,2,3\n"),
               "pass.csv: line 1: expected the header time_s,x_mm,y_mm,force_n");
  CHECK_STARTS(RefusedTrajectory(""), "pass.csv: line 1: expected the header");
  CHECK_STARTS(RefusedTrajectory(h), "pass.csv: no samples");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2\n"), "pass.csv: line 2: 3 values, expected 4");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2,3,4\n"), "pass.csv: line 2: more than 4 values");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2,1\n\n0,1,y,1\n"),
               "pass.csv: line 4, value 3: \"y\" is not a");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2,1\n0.5,1,2,1\n0.5,1,2,1\n"),
               "pass.csv: line 4: time 0.5 s is not after line 3's 0.5 s");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2,-0.1\n"),
               "pass.csv: line 2: force -0.1 N is outside 0 … 100 N");
  CHECK_STARTS(RefusedTrajectory(h + "0,1,2,inf\n"),
               "pass.csv: line 2, value 4: \"inf\" is not a number");
}

TEST(SceneTrajectory, FilesAreReadWithinTheirCap) {
  char pattern[] = "/tmp/palpa-trajectory-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const std::string path = dir + "/pass.csv";
  std::ofstream(path) << Pass(30);
  const auto t = ph::LoadTrajectory(path);
  CHECK_TEXT(t.ok(), t.message.c_str());
  LONGS_EQUAL(4001, t.value.size());  // 120 mm at 30 mm/s, 1 kHz
  CHECK(truncate(path.c_str(), ph::kTrajectoryLimits.max_bytes + 1) == 0);
  CHECK_STARTS(ph::LoadTrajectory(path).message, path + ": larger than the 64 MiB limit");
  CHECK_STARTS(ph::LoadTrajectory(dir + "/none.csv").message, dir + "/none.csv: cannot be read");
  CHECK(std::system(("rm -rf " + dir).c_str()) == 0);
}

TEST(SceneTrajectory, APassRendersTheSameEveryTimeWithEachEdgeWhereItsCubeIs) {
  const auto samples = ph::ParseTrajectory(Pass(30), "pass.csv").value;
  const ph::RenderFinger finger{
      0, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, 0, pp::kNoLine}, {}};
  const auto r = ph::SceneRenderer::Make(ph::GeneratePhantom(ph::ThreeCubePhantom()).value,
                                         ph::RowLayout(1, 10, 4), {}, {finger});
  CHECK_TEXT(r.ok(), r.message.c_str());
  std::vector<int32_t> first;
  for (const ph::SceneInput& s : samples) first.push_back(r.value.Render(s)[0].mapped.target);
  for (size_t k = 0; k < samples.size(); ++k)
    LONGS_EQUAL(first[k], r.value.Render(samples[k])[0].mapped.target);
  // Where the finger's target first crosses half of cube B's: its disc half over B's near edge
  // (x = 54 mm), within a sample's travel and the map's pitch.
  const double half_b = r.value.Render({0, 60, 15, 1})[0].mapped.target / 2.0;
  double crossed = -1;
  for (size_t k = 0; k < samples.size() && crossed < 0; ++k) {
    if (samples[k].x_mm > 45 && first[k] >= half_b) crossed = samples[k].x_mm;
  }
  DOUBLES_EQUAL(54, crossed, 0.5);
}
