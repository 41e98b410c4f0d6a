// palpa scene and palpa render: a phantom's tissue file written (the preset and a block of one's
// own) and read back, a scene drawn as SVG, every wrong argument named; a trajectory rendered on
// palpa-sim and recorded, at its own pace on the board's clock, and shown live on a terminal.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_run.h"
#include "palpa/host/scene_files.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;

namespace {

const std::string kExample = std::string(PALPA_DOCS_DIR) + "/examples/scene_three_cube.json";

}  // namespace

TEST_GROUP(CliScene){};

TEST(CliScene, PhantomsAreWrittenAsTissueFilesThatReadBack) {
  const std::string out = OwnTempPath("three.json");
  auto r = Palpa("scene phantom --preset thesis-three-cube --out " + out);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "241 × 61 points over 120 × 30 mm, 14.7 … 36.2473 kPa"), r.output.c_str());
  auto map = palpa::host::LoadTissue(out);
  CHECK_TEXT(map.ok(), map.message.c_str());
  LONGS_EQUAL(241, map.value.nx);
  r = Palpa(
      "--json scene phantom --size 50,20,10 --background 10 --inclusion 25,10,5,5,2,100 "
      "--pitch 1 --name mine --out " +
      out);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "\"name\":\"mine\"") && Has(r, "\"points\":[51,21]"), r.output.c_str());
  map = palpa::host::LoadTissue(out);
  CHECK_TEXT(map.ok(), map.message.c_str());
  DOUBLES_EQUAL(10 / (5.0 / 10 + 5.0 / 100), map.value.At(25, 10), 1e-9);
  std::remove(out.c_str());
}

TEST(CliScene, AScenesMapAndFingersAreDrawn) {
  const std::string out = OwnTempPath("scene.svg");
  const auto r = Palpa("scene show " + kExample + " --at 60,12 --out " + out);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const std::string svg = palpa::testing::Slurp(out);
  CHECK(svg.rfind("<svg ", 0) == 0);
  CHECK(svg.find("three-cube, three fingers — right triangle, 15 mm") != std::string::npos);
  std::remove(out.c_str());
}

TEST(CliScene, WrongArgumentsAreNamed) {
  const std::string out = OwnTempPath("x.json");
  ExpectUsage("scene", "phantom, show or calibrate-input");
  ExpectUsage("scene shw", "unknown subcommand shw (did you mean show?)");
  ExpectUsage("scene phantom --out " + out, "either --preset NAME or --size");
  ExpectUsage("scene phantom --preset liver --out " + out, "the presets are thesis-three-cube");
  ExpectUsage("scene phantom --preset thesis-three-cube", "--out FILE");
  ExpectUsage("scene phantom --size 50,20 --background 10 --out " + out,
              "--size 50,20: expected 3 numbers");
  ExpectUsage(
      "scene phantom --size 50,20,10 --background 10 --inclusion 25,10,5,5,6,100 --out " + out,
      "phantom block: --inclusion 1: depth_mm: 6 + thickness 5 mm does not fit");
  ExpectUsage(
      "scene phantom --size 50,20,10 --background 10 --inclusion 25,10,5,5,2,100 "
      "--inclusion 26,10,5,5,1,100 --out " +
          out,
      "phantom block: --inclusion 2: overlaps --inclusion 1");
  ExpectUsage("scene phantom --size 50,20,10 --background soft --out " + out,
              "--background soft: expected a number");
  ExpectUsage("scene show " + out + " --out x.svg", "cannot be read");
  ExpectUsage("scene show --out x.svg", "a SCENE file and --out FILE.svg");
  ExpectUsage("scene show " + kExample + " --at 1 --out x.svg", "--at 1: expected 2 numbers");
}

TEST(CliScene, ATrajectoryIsRenderedToTheBoardAndRecorded) {
  const std::string input = OwnTempPath("pass.csv"), record = OwnTempPath("run.csv");
  {
    std::ofstream pass(input);
    pass << "time_s,x_mm,y_mm,force_n\n";
    for (int k = 0; k <= 100; ++k) pass << k * 0.004 << "," << 40 + k * 0.2 << ",12,1\n";
  }
  const std::string svg = record.substr(0, record.size() - 4) + ".svg";
  const auto r = Palpa("--device sim:thesis-pneumatic-3 render " + kExample + " --input " + input +
                           " --record " + record,
                       std::string("PALPA_SIM=") + PALPA_SIM_PATH);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "101 of 101 samples rendered; recorded in " + record), r.output.c_str());
  const std::string csv = palpa::testing::Slurp(record);
  CHECK(csv.rfind("time_s,x_mm,y_mm,force_n,board_time_us,finger1_touching,finger1_value,"
                  "finger1_target,",
                  0) == 0);
  LONGS_EQUAL(102, std::count(csv.begin(), csv.end(), '\n'));
  // The last sample: finger 1 at x = 60 on cube B, at the top of the stress range (30 kPa →
  // 1.164 mm on Table 5-4's line); finger 2 at x = 75 on the block.
  CHECK_TEXT(csv.find("0.400000,60.0000,12.0000,1.0000,") != std::string::npos, csv.c_str());
  CHECK(csv.find(",1,36.2473,1.164,1,14.7,0,") != std::string::npos);
  CHECK(palpa::testing::Slurp(svg).find("<polyline") != std::string::npos);
  ExpectUsage("render " + kExample, "a SCENE file and --input TRAJECTORY.csv");
  ExpectUsage("render " + kExample + " --input " + record, "expected the header time_s,x_mm");
  for (const std::string& f : {input, record, svg}) std::remove(f.c_str());
}

TEST(CliScene, ATrajectoryKeepsItsPaceOnTheBoardsClockWhateverTheSimulatorsSpeed) {
  // A board ten times faster than real time (palpa sim start --speed 10) takes a 6 s trajectory
  // in about 6 s of its own time: the record's board times span what the trajectory's do, not
  // ten times as much (samples paced in real time would be).
  char pattern[] = "/tmp/palpa-cli-state-XXXXXX";
  const std::string state = mkdtemp(pattern);
  const std::string env = "PALPA_STATE_DIR=" + state + " PALPA_SIM=" + PALPA_SIM_PATH + " ";
  const std::string input = state + "/pass.csv", record = state + "/run.csv";
  {
    std::ofstream pass(input);
    pass << "time_s,x_mm,y_mm,force_n\n";
    for (int k = 0; k <= 150; ++k) pass << k * 0.04 << "," << 40 + k * 0.1 << ",12,1\n";
  }
  auto r = Palpa("sim start --config thesis-pneumatic-3 --speed 10", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("render " + kExample + " --input " + input + " --record " + record, env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  Palpa("sim stop", env);
  // time_s and board_time_us of the first row telemetry had reached, and of the last.
  std::istringstream rows(palpa::testing::Slurp(record));
  std::string row;
  std::getline(rows, row);  // the header
  double first_t = -1, first_us = 0, last_t = 0, last_us = 0;
  while (std::getline(rows, row)) {
    double t = 0, x, y, f, us = 0;
    char comma;
    std::istringstream(row) >> t >> comma >> x >> comma >> y >> comma >> f >> comma >> us;
    if (us == 0) continue;
    if (first_t < 0) first_t = t, first_us = us;
    last_t = t, last_us = us;
  }
  std::system(("rm -rf " + state).c_str());
  CHECK_TEXT(first_t >= 0 && last_t - first_t > 5, "no telemetry reached the record");
  const double board_span_s = (last_us - first_us) / 1e6, trajectory_span_s = last_t - first_t;
  CHECK_TEXT(board_span_s > 0.5 * trajectory_span_s && board_span_s < 3 * trajectory_span_s,
             (std::to_string(board_span_s) + " s of board time for " +
              std::to_string(trajectory_span_s) + " s of trajectory")
                 .c_str());
}

TEST(CliScene, OnATerminalEachSampleIsShownAsItGoes) {
  // On a terminal (script(1) gives the command one) each sample's input and every finger's target
  // take one line that the next sample overwrites; through a pipe only the summary is printed.
  const std::string input = OwnTempPath("live.csv");
  {
    std::ofstream pass(input);
    pass << "time_s,x_mm,y_mm,force_n\n0,40,12,1\n0.01,41,12,1\n0.02,42,12,1\n";
  }
  const std::string command = "env -u PALPA_DEVICE PALPA_STATE_DIR=/nonexistent-palpa-state " +
                              std::string("PALPA_SIM=") + PALPA_SIM_PATH + " " + PALPA_CLI_PATH +
                              " --device sim:thesis-pneumatic-3 render " + kExample + " --input " +
                              input;
  const auto live = palpa::testing::Shell("script -qec '" + command + "' /dev/null");
  LONGS_EQUAL_TEXT(0, live.code, live.output.c_str());
  // Finger 2 (x + 15 mm) on cube B's face and then over it; fingers 1 and 3 on the block.
  CHECK_TEXT(
      Has(live, "\r  0.000 s  x   40.0  y   12.0 mm  1.00 N  targets  0.000  0.984  0.000\r"),
      live.output.c_str());
  CHECK_TEXT(Has(live, "\r  0.020 s  x   42.0  y   12.0 mm  1.00 N  targets  0.000  1.164  0.000"),
             live.output.c_str());
  CHECK_TEXT(Has(live, "3 of 3 samples rendered"), live.output.c_str());
  const auto piped = palpa::testing::Shell(command);
  LONGS_EQUAL_TEXT(0, piped.code, piped.output.c_str());
  CHECK_TEXT(Has(piped, "3 of 3 samples rendered"), piped.output.c_str());
  CHECK_FALSE(Has(piped, "targets"));
  std::remove(input.c_str());
}
