// The palpa command line as a person uses it: exit codes, named errors, nothing sent on a bad
// command line, and the commands against palpa-sim.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "mini_client.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliUsage){};

TEST(CliUsage, HelpForEveryCommand) {
  for (const char* command : {"list", "info", "diag", "config", "set", "line", "monitor", "record",
                              "estop", "clear", "demo", "calibrate", "flash", "package"}) {
    const Run r = Palpa(std::string(command) + " --help");
    LONGS_EQUAL_TEXT(0, r.code, command);
    CHECK_TEXT(Has(r, "usage: palpa"), command);
  }
  CHECK(Has(Palpa("--help"), "Exit codes"));
}

TEST(CliUsage, MalformedCommandLinesNameTheArgumentAndSendNothing) {
  // The device does not exist: a usage error must come before any attempt to open it.
  const std::string nowhere = "--device tcp:127.0.0.1:1 ";
  Run r = ExpectUsage(nowhere + "set 1=L2x", "'1=L2x'");
  r = ExpectUsage(nowhere + "set 9=L1", "finger must be a number from 1 to 8");
  r = ExpectUsage(nowhere + "set 2=1.7", "normalised stiffness from 0 to 1");
  r = Palpa(nowhere + "set 4=0.9N/m");
  LONGS_EQUAL(2, r.code);
  r = ExpectUsage(nowhere + "line 1=abc", "'1=abc'");
  r = ExpectUsage(nowhere + "monitor --rate fast", "--rate");
  r = ExpectUsage(nowhere + "record out.csv", "--duration");
  r = ExpectUsage(nowhere + "frobnicate", "unknown command 'frobnicate'");
  r = Palpa("--device");
  LONGS_EQUAL(2, r.code);
  // The demo's chart is written at its end: a place it cannot be written is refused first.
  r = ExpectUsage("demo --out /nonexistent-dir/chart.svg", "/nonexistent-dir is not a directory");
  CHECK_FALSE(Has(r, "starting a simulated"));
  r = ExpectUsage("demo --out", "--out needs a file name");
  r = ExpectUsage("demo --speed 20", "--speed needs a number from 0.1 to 10");
  r = ExpectUsage("demo --calibration /nonexistent-dir",
                  "--calibration /nonexistent-dir: not a directory");
  r = ExpectUsage("demo --nominal-only --calibration /tmp", "exclude each other");
  const std::string bad = OwnTempPath("bad.json");
  std::ofstream(bad) << "{\"board\": {\"host_timeout_us\": 1e3.5}";
  r = Palpa(nowhere + "config load " + bad);
  std::remove(bad.c_str());
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "not valid JSON"));
}

TEST(CliUsage, UnreachableDeviceIsExitCodeThree) {
  const Run r = Palpa("--device tcp:127.0.0.1:1 info");
  LONGS_EQUAL(3, r.code);
  CHECK(Has(r, "tcp:127.0.0.1:1"));
}

TEST_GROUP(CliBoard) {
  palpa::testing::SimProcess sim;
  std::string device;
  void setup() override {
    CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0"}));
    device = "--device " + sim.address() + " ";
  }
  void teardown() override { sim.Stop(); }
};

TEST(CliBoard, InfoAndDiag) {
  Run r = Palpa(device + "--json info");
  LONGS_EQUAL(0, r.code);
  const auto j = nlohmann::json::parse(r.output);
  LONGS_EQUAL(5, j["fingers"].size());
  STRCMP_EQUAL("jamming", j["fingers"][3]["kind"].get<std::string>().c_str());
  r = Palpa(device + "info");
  CHECK(Has(r, "finger 4      jamming"));
  r = Palpa(device + "--json diag");
  LONGS_EQUAL(0, r.code);
  CHECK(nlohmann::json::parse(r.output).contains("loop"));
}

TEST(CliBoard, SetChecksUnitsPerFingerKind) {
  Run r = Palpa(device + "set 1=L2 2=0.5 3=1.2mm 4=0.9N/mm 5=-10kPa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "nominal thesis curves"));
  r = Palpa(device + "set 1=0.9N/mm");
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "N/mm means nothing for a pneumatic finger"));
  r = Palpa(device + "set 4=2.0N/mm");
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "outside the calibrated range"));
  r = Palpa(device + "line 4=30");  // a bias line: 20 kPa at most
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "outside its limits"));
}

TEST(CliBoard, ConfigSetIsValidatedThenAppliedAndShown) {
  Run r = Palpa(device + "config set board.host_timeout_us=250000 line2.slew_pa_per_s=150000");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa(device + "--json config show");
  const auto j = nlohmann::json::parse(r.output);
  LONGS_EQUAL(250000, j["board"]["host_timeout_us"].get<int>());
  LONGS_EQUAL(150000, j["lines"][1]["slew_pa_per_s"].get<int>());
  r = Palpa(device + "config set line4.limit_max_pa=30000");  // beyond the bias ceiling
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "line 4"));
  CHECK(Has(r, "nothing was sent"));
  r = ExpectUsage(device + "config set line2.no_such_field=1", "no_such_field");
}

TEST(CliBoard, MonitorRecordEstopClear) {
  Run r = Palpa(device + "--json monitor --rate 50 --duration 0.5");
  LONGS_EQUAL(0, r.code);
  const std::string first = r.output.substr(0, r.output.find('\n'));
  CHECK(nlohmann::json::parse(first)["lines"].size() == 7);
  const std::string recording = OwnTempPath("record.csv");
  r = Palpa(device + "record " + recording + " --duration 0.5");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  std::string header;
  std::getline(std::ifstream(recording), header);
  std::remove(recording.c_str());
  CHECK(header.rfind("# {", 0) == 0);
  LONGS_EQUAL(0, Palpa(device + "estop").code);
  r = Palpa(device + "--json diag");
  CHECK(nlohmann::json::parse(r.output)["faults_latched"].get<int>() != 0);
  LONGS_EQUAL(0, Palpa(device + "clear").code);
}

TEST_GROUP(CliCalibrate){};

TEST(CliCalibrate, BadArgumentsAreNamedBeforeAnythingStarts) {
  const std::string nowhere = "--device tcp:127.0.0.1:1 ";
  Run r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1", "--out DIR");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 9 --out /tmp", "--finger 9");
  // A refused command creates nothing, not even its output directory.
  const std::string never = OwnTempPath("never");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out " + never,
                  "--rig sim goes with a simulated device");
  CHECK(access(never.c_str(), F_OK) != 0);
  const std::string rig = OwnTempPath("rig.json");
  std::ofstream(rig) << "{\"name\": \"lab\", \"stage\": {\"driver\": \"modbus\"}}";
  r = Palpa(nowhere + "calibrate --rig " + rig + " --finger 1 --out /tmp");
  std::remove(rig.c_str());
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "stage.address: missing"));
  r = ExpectUsage("calibrate --rig sim --finger 1 --out " + never + " --resume", "no journal");
  CHECK(access(never.c_str(), F_OK) != 0);
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 4 --out /tmp --protocol fast",
                  "--protocol fast: expected thesis or adaptive");
  r = ExpectUsage(
      nowhere + "calibrate --rig sim --finger 4 --out /tmp --protocol adaptive --target 0",
      "--target 0");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 4 --out /tmp --max-cycles 3",
                  "--max-cycles 3: expected 6 to 200");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --compensator branch",
                  "--compensator branch: expected auto, pi or api");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --compensator api:40",
                  "--compensator api:40");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --speed 20",
                  "--speed 20: expected 1 to 10");
  r = ExpectUsage(
      "calibrate --rig sim --finger 4 --out /tmp --previous /tmp/palpa-cli-no-such.json",
      "palpa-cli-no-such.json");
}

TEST(CliCalibrate, QuickCalibrationOnTheSimulatedRigWritesAValidFileRawDataAndAReport) {
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const Run r = Palpa("calibrate --rig sim --finger 1 --quick --apply --out " + dir);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "calibrated PN-1"));
  CHECK(Has(r, "applied to finger 1"));
  std::ifstream file(dir + "/PN-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  // Left to choose, calibration fits both play models and keeps api on the film's loop.
  CHECK(j["compensator"]["kind"] == "api");
  CHECK(Has(r, "model chosen (auto): api: api(8) "));
  CHECK(j["static_inverse"].size() >= 8);
  std::ifstream html(dir + "/PN-1.html");
  std::string report((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  CHECK(report.find("<svg") != std::string::npos);
  CHECK(report.find("Regulator static correction") != std::string::npos);
  CHECK(access((dir + "/PN-1.journal.json").c_str(), F_OK) !=
        0);  // a finished run leaves no journal
}

TEST(CliCalibrate, AdaptiveMapOnAJammingFingerReportsItsChecks) {
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const Run r = Palpa(
      "calibrate --rig sim --finger 4 --quick --protocol adaptive --max-cycles 8 --out " + dir);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "stiffness map: adaptive, 8 cycles"));
  for (const char* check : {"check points", "check noise", "check force_zero", "check leak"})
    CHECK_TEXT(Has(r, check), check);
  std::ifstream file(dir + "/JAM-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  CHECK(j["quality"]["protocol"] == "adaptive");
  LONGS_EQUAL(4, j["quality"]["checks"].size());
  std::ifstream html(dir + "/JAM-1.html");
  std::string report((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  CHECK(report.find("what was measured") != std::string::npos);
  // A calibration of another actuator is refused as its previous one.
  nlohmann::json other = j;
  other["actuator_serial"] = "JAM-2";
  std::ofstream(dir + "/other.json") << other.dump();
  const Run refused = Palpa("calibrate --rig sim --finger 4 --quick --out " + dir + " --previous " +
                            dir + "/other.json");
  LONGS_EQUAL(2, refused.code);
  CHECK(Has(refused, "calibrates JAM-2, not JAM-1"));
}

TEST_GROUP(CliFlash){};

TEST(CliFlash, PackagesAreMadeCheckedAndFlashedOverTheLink) {
  char pattern[] = "/tmp/palpa-flash-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  std::ofstream(dir + "/a.bin") << std::string(20000, 'a');
  std::ofstream(dir + "/b.bin") << std::string(20000, 'b');
  Run r = Palpa("package " + dir + "/a.bin " + dir + "/b.bin --version 0.3.0 --counter 3 --out " +
                dir + "/new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("package " + dir + "/a.bin " + dir + "/b.bin --version 0.0.9 --counter 0 --out " + dir +
            "/old.palpa");
  LONGS_EQUAL(0, r.code);
  // Bad command lines and bad packages are named before anything is sent.
  const std::string nowhere = "--device tcp:127.0.0.1:1 ";
  r = ExpectUsage(nowhere + "flash", "needs a PACKAGE");
  r = ExpectUsage(nowhere + "flash " + dir + "/missing.palpa", "cannot be read");
  std::ofstream(dir + "/text.palpa") << "hello";
  r = ExpectUsage(nowhere + "flash " + dir + "/text.palpa", "not a palpa update package");
  {
    std::ifstream in(dir + "/new.palpa", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir + "/cut.palpa", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  r = ExpectUsage(nowhere + "flash " + dir + "/cut.palpa", "truncated");
  r = ExpectUsage(nowhere + "flash " + dir + "/new.palpa --reset-line gpiochip9:1",
                  "--reset-line 'gpiochip9:1': no GPIO chip");
  r = Palpa("package " + dir + "/a.bin --version 1 --counter 1 --out x");
  LONGS_EQUAL(2, r.code);

  palpa::testing::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"}));
  const std::string device = "--device " + sim.address() + " ";
  r = Palpa(device + "flash " + dir + "/new.palpa --dry-run");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "would write 0.3.0"));
  r = Palpa(device + "flash " + dir + "/new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "updated 0.1.0 → 0.3.0 (slot 1), confirmed"));
  r = Palpa(device + "info");
  CHECK(Has(r, "firmware      0.3.0"));
  CHECK(Has(r, "image slot    1, anti-rollback counter 3"));
  r = ExpectUsage(device + "flash " + dir + "/old.palpa",
                  "anti-rollback counter 0 is below the board's 3");
}

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
  CHECK_TEXT(Has(r, "calibrated, api(8)"), r.output.c_str());
  const auto worst = SummaryRow(r, "pneumatic fingers: largest |error| / target");
  const auto gap = SummaryRow(r, "level 1 from above minus from below");
  // Nominal: the film's loop (0.18 against 0.36 mm at one target); calibrated: a few percent.
  CHECK_TEXT(worst.first > 30, r.output.c_str());
  CHECK_TEXT(worst.second >= 0 && worst.second < 10, r.output.c_str());
  CHECK_TEXT(gap.first > 100, r.output.c_str());
  CHECK_TEXT(std::fabs(gap.second) < 40, r.output.c_str());
}
