// palpa render's live and tactile inputs: a recorded tactile stream played to palpa-sim (fingers
// soft through a stall longer than the hold), frames over UDP with a malformed one counted,
// prediction refused where the fingers' delay is not calibrated, and every wrong input named.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "palpa/host/scene_file.h"
#include "palpa/host/scene_tactile.h"
// After the library headers: CppUTest's allocation macros break the standard library ones.
#include "cli_run.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::ExpectUsage;
using palpa::testing::FreeUdpPort;
using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;

namespace {

const std::string kDocs = PALPA_DOCS_DIR;
const std::string kInputs = kDocs + "/examples/scene_inputs.json";
const std::string kStream = kDocs + "/examples/tactile_grasper.csv";
const std::string kSim = std::string("PALPA_SIM=") + PALPA_SIM_PATH;

}  // namespace

TEST_GROUP(CliSceneInput){};

TEST(CliSceneInput, ARecordedTactileStreamIsPlayedAndGoesSoftInAStall) {
  const std::string record = OwnTempPath("tactile.csv");
  const auto r = Palpa("--device sim:thesis-pneumatic-3 render " + kInputs +
                           " --input tactile-file:" + kStream + " --record " + record,
                       kSim);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "267 of 267 frames rendered; recorded in " + record + "\n"), r.output.c_str());
  const std::string csv = palpa::testing::Slurp(record);
  CHECK(csv.rfind("time_s,board_time_us,finger1_touching,finger1_value,finger1_target,", 0) == 0);
  // The first frame: row 0 at 0 kPa (released), row 1's mean 20 kPa of 0 … 40 (half the stress
  // range: 0.477 mm), row 2's 15 kPa.
  CHECK_TEXT(csv.find("\n0.000000,") != std::string::npos, csv.c_str());
  CHECK(csv.find(",1,20,0.477,1,15,") != std::string::npos);
  // 0.1 s after the last frame before the stall (1.49 s), every finger soft, until 1.80 s.
  size_t soft_rows = 0;
  std::istringstream rows(csv);
  std::string row;
  while (std::getline(rows, row)) {
    if (row.find(",0,0,0,0,0,0,0,0,0") != std::string::npos) {
      const double t = std::stod(row);
      CHECK_TEXT((t > 1.59 && t < 1.80) || t > 2.99, row.c_str());
      ++soft_rows;
    }
  }
  CHECK(soft_rows >= 1);
  // No path over the tissue, so no SVG of one.
  CHECK(palpa::testing::Slurp(record.substr(0, record.size() - 4) + ".svg").empty());
  std::remove(record.c_str());
}

TEST(CliSceneInput, TactileFramesOverUdpMalformedOnesCounted) {
  const uint16_t port = static_cast<uint16_t>(FreeUdpPort());
  std::atomic<bool> done{false};
  std::thread sender([&] {
    const int s = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    for (uint32_t seq = 0; !done && seq < 2000; ++seq) {
      const auto b = seq % 50 == 7
                         ? palpa::host::EncodeTactilePacket(seq, {1, 2})
                         : palpa::host::EncodeTactilePacket(seq, std::vector<double>(9, 20));
      sendto(s, b.data(), b.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
      usleep(10000);
    }
    close(s);
  });
  const auto r =
      Palpa("--json --device sim:thesis-pneumatic-3 render " + kInputs +
                " --input tactile-udp:127.0.0.1:" + std::to_string(port) + " --duration 1.5",
            kSim);
  done = true;
  sender.join();
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "\"input\":\"tactile-udp:127.0.0.1:" + std::to_string(port) + "\""),
             r.output.c_str());
  CHECK_TEXT(Has(r, "\"malformed\":") && !Has(r, "\"malformed\":0"), r.output.c_str());
  CHECK_TEXT(!Has(r, "\"samples\":0,"), r.output.c_str());
}

TEST(CliSceneInput, PredictionNeedsCalibratedFingers) {
  const std::string input = OwnTempPath("pass.csv");
  {
    std::ofstream pass(input);
    pass << "time_s,x_mm,y_mm,force_n\n0,40,12,1\n0.01,40.3,12,1\n";
  }
  const auto r = Palpa("--device sim:thesis-pneumatic-3 render " + kDocs +
                           "/examples/scene_three_cube.json --input " + input + " --predict",
                       kSim);
  LONGS_EQUAL_TEXT(1, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "--predict: finger 1: line 1 has no chamber model"), r.output.c_str());
  std::remove(input.c_str());
}

TEST(CliSceneInput, WrongInputsAreNamed) {
  ExpectUsage("render " + kInputs + " --input foo:bar",
              "--input foo:bar: unknown input kind \"foo\"");
  ExpectUsage("render " + kInputs + " --input tactile-udp:0", "the port must be 1 … 65535");
  ExpectUsage("render " + kInputs + " --input tactile-udp:host:x", "the port must be 1 … 65535");
  ExpectUsage("render " + kInputs + " --input evdev:", "evdev: needs the event node's path");
  ExpectUsage("render " + kInputs + " --input tactile-udp::5555",
              "an empty address before the port");
  ExpectUsage("render " + kInputs + " --input tactile-file:" + kStream + " --predict",
              "a tactile array has no position to predict");
  ExpectUsage("render " + kInputs + " --input tactile-file:" + kStream + " --duration 2",
              "--duration is for live inputs");
  ExpectUsage("render " + kInputs + " --input evdev:/dev/null --duration x",
              "--duration x: a number of seconds above 0");
  ExpectUsage("render " + kDocs + "/examples/scene_three_cube.json --input tactile-file:" + kStream,
              "a tactile input needs the scene's input.tactile section");
  ExpectUsage(
      "render " + kInputs + " --input tactile-file:" + kDocs + "/examples/scene_inputs.json",
      "expected the header time_s");
  const auto r =
      Palpa("--device sim:thesis-pneumatic-3 render " + kInputs + " --input evdev:/dev/null", kSim);
  LONGS_EQUAL_TEXT(3, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "/dev/null: not an input event device"), r.output.c_str());
}

TEST(CliSceneInput, PenPressureFormSetOrFittedIntoTheSceneFile) {
  const std::string scene = OwnTempPath("pen.json"), presses = OwnTempPath("presses.csv");
  {
    std::ofstream out(scene);
    out << palpa::testing::Slurp(kDocs + "/examples/scene_three_cube.json");
    std::ofstream p(presses);
    p << "level,force_n\n# level, what the sensor read\n100,0.1477\n400,0.4759\n700,1.5333\n"
         "1000,4.9402\n";
  }
  auto r = Palpa("scene calibrate-input " + scene + " --a 0.09 --b 0.0035");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "pen pressure f = 0.09 · e^(0.0035 · level) N"), r.output.c_str());
  CHECK(palpa::testing::Slurp(scene).find("\"b_per_level\": 0.0035") != std::string::npos);
  CHECK(palpa::testing::Slurp(scene).find("\"preset\": \"thesis-three-cube\"") !=
        std::string::npos);
  r = Palpa("--json scene calibrate-input " + scene + " --presses " + presses);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  // The presses lie on 0.1 · e^(0.0039 · level) to four digits.
  CHECK_TEXT(Has(r, "\"presses\":4"), r.output.c_str());
  const auto back = palpa::host::LoadScene(scene);
  CHECK_TEXT(back.ok() && back.value.tablet, back.message.c_str());
  DOUBLES_EQUAL(0.1, back.value.tablet->pressure_force.a_n, 1e-4);
  DOUBLES_EQUAL(0.0039, back.value.tablet->pressure_force.b_per_level, 1e-6);
  ExpectUsage("scene calibrate-input " + scene, "one of --a A --b B, --presses PRESSES.csv");
  ExpectUsage("scene calibrate-input " + scene + " --a 1", "--a and --b go together");
  ExpectUsage("scene calibrate-input " + scene + " --a 0 --b 0.1",
              "--a, --b: pressure_force: a = 0 N");
  ExpectUsage("scene calibrate-input " + scene + " --a 1 --b 0.1 --presses " + presses,
              "one of --a A --b B");
  ExpectUsage("scene calibrate-input " + scene + " --pen evdev:/dev/input/event3",
              "--pen and --rig go together");
  ExpectUsage("scene calibrate-input " + scene + " --presses " + scene,
              ": line 1: expected the header level,force_n");
  {
    std::ofstream p(presses);
    p << "level,force_n\n100,0.2\n100,0.3\n";
  }
  ExpectUsage("scene calibrate-input " + scene + " --presses " + presses,
              presses + ": presses: 2 presses; the fit needs at least two at different levels");
  r = Palpa("scene calibrate-input " + scene + " --pen evdev:/dev/null --rig " + scene);
  LONGS_EQUAL_TEXT(3, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "/dev/null: not an input event device"), r.output.c_str());
  std::remove(scene.c_str());
  std::remove(presses.c_str());
}
