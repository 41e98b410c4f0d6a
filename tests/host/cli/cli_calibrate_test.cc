// palpa calibrate on the simulated rig: bad arguments named before anything starts, the unit,
// compensator fallback, a failed fit keeping its journal, the quick and adaptive runs.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"
#include "palpa/calibration/calibration_protocol.h"

using palpa::testing::ExpectUsage;
using palpa::testing::FileText;
using palpa::testing::Has;
using palpa::testing::kNowhere;
using palpa::testing::MakeTempDir;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

namespace {

// Each group below that calibrates is a CTest entry of its own, so they run side by side. Those
// that hold what the command does with a calibration (its files, its fallback, its report), not
// the values the rig reads, run palpa-sim at its top speed, `--speed 10`; the unit test, which
// holds the readings, runs at calibrate's default speed, as the readings it was set on were taken.
std::string OnTheSimRig(const std::string& args) {
  return "calibrate --rig sim --speed 10 " + args;
}

}  // namespace

TEST_GROUP(CliCalibrate){};

TEST(CliCalibrate, BadArgumentsAreNamedBeforeAnythingStarts) {
  Run r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1", "--out DIR");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 9 --out /tmp", "--finger 9");
  // A refused command creates nothing, not even its output directory.
  const std::string never = OwnTempPath("never");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out " + never,
                  "--rig sim goes with a simulated device");
  CHECK(access(never.c_str(), F_OK) != 0);
  const std::string rig = OwnTempPath("rig.json");
  std::ofstream(rig) << "{\"name\": \"lab\", \"stage\": {\"driver\": \"modbus\"}}";
  r = Palpa(kNowhere + "calibrate --rig " + rig + " --finger 1 --out /tmp");
  std::remove(rig.c_str());
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "stage.address: missing"));
  r = ExpectUsage("calibrate --rig sim --finger 1 --out " + never + " --resume", "no journal");
  CHECK(access(never.c_str(), F_OK) != 0);
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 4 --out /tmp --protocol fast",
                  "--protocol fast: expected thesis or adaptive");
  r = ExpectUsage(
      kNowhere + "calibrate --rig sim --finger 4 --out /tmp --protocol adaptive --target 0",
      "--target 0");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 4 --out /tmp --max-cycles 3",
                  "--max-cycles 3: expected 6 to 200");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --compensator branch",
                  "--compensator branch: expected auto, pi or api");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --compensator api:40",
                  "--compensator api:40");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --speed 20",
                  "--speed 20: expected 1 to 10");
  r = ExpectUsage(
      "calibrate --rig sim --finger 4 --out /tmp --previous /tmp/palpa-cli-no-such.json",
      "palpa-cli-no-such.json");
  // The rig's simulator: its options are checked here, go with --rig sim only, and an
  // environment variable it would not read is refused rather than ignored.
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --unit 1001",
                  "--unit 1001: expected an actuator unit 0 to 1000");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --plant 2.5",
                  "--plant 2.5: expected a plant level 0 to 3");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --effects creep,wind",
                  "--effects creep,wind: unknown effect 'wind'");
  r = ExpectUsage(kNowhere + "calibrate --rig sim --finger 1 --out /tmp --effects history=0.9",
                  "history wants a fraction of 0 to 0.5");
  r = ExpectUsage(kNowhere + "calibrate --rig lab.json --finger 1 --out /tmp --unit 2",
                  "go with --rig sim");
  r = Palpa("calibrate --rig sim --finger 1 --quick --out " + never, "PALPA_SIM_ARGS='--unit 2'");
  LONGS_EQUAL_TEXT(2, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "PALPA_SIM_ARGS ('--unit 2') is not read by --rig sim"), r.output.c_str());
  CHECK(access(never.c_str(), F_OK) != 0);
}

TEST_GROUP(CliCalibrateUnits){};

TEST(CliCalibrateUnits, ACalibrationOfSimulatedUnit12IsOfUnit12AndSaysSo) {
  // The unit reaches palpa-sim, and what the command says and records is the plant palpa-sim
  // announced it runs: a command line that dropped --unit, or a library that did not pass it on,
  // would say unit 0 here (or refuse the run). That a calibration of unit 12 then finds unit
  // 12's own slopes, not the nominal unit's, is CalibrationUnits (virtual time, so the comparison
  // does not depend on how busy the machine is).
  const std::string dir = MakeTempDir("palpa-cal-cli");
  const Run r =
      Palpa("calibrate --rig sim --finger 1 --quick --speed 10 --unit 12 --seed 3 --out " + dir);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "calibrated PN-1 (finger 1, simulated unit 12, seed 3, plant level 3)"),
             r.output.c_str());
  // Its progress went to a pipe: lines, not a bar redrawn with carriage returns.
  CHECK_TEXT(r.output.find('\r') == std::string::npos, r.output.c_str());
  CHECK_TEXT(Has(r, "] "), r.output.c_str());
  std::ifstream file(dir + "/PN-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  CHECK(j["simulation"] ==
        nlohmann::json::parse(
            R"({"actuator_unit": 12, "seed": 3, "plant_level": 3, "effects": ""})"));
  CHECK(j["fits"]["rising"]["slope"].get<double>() > 0);
}

TEST_GROUP(CliCalibrateFallback){};

TEST(CliCalibrateFallback, ACompensatorTheSweepCannotFitIsAnErrorUnlessFallingBackIsAllowed) {
  // Refused before the run: the quick sweep says what it can fit, and pi(32) is not among it.
  const std::string never = OwnTempPath("never-fitted");
  Run r = Palpa("calibrate --rig sim --finger 1 --quick --compensator pi:32 --out " + never);
  LONGS_EQUAL_TEXT(2, r.code, r.output.c_str());
  CHECK_TEXT(Has(r,
                 "hysteresis sweep (--quick): 53 readings in 10 kPa steps (pi up to 24 "
                 "operators, api up to 20"),
             r.output.c_str());
  CHECK(Has(r, "pi(32) needs 68 sweep readings; this sweep has 53"));
  CHECK(access(never.c_str(), F_OK) != 0);  // nothing written, not even the directory
  // Allowed to fall back, the run keeps the static inverse alone and says why, in the file too.
  const std::string dir = MakeTempDir("palpa-cal-cli");
  r = Palpa(OnTheSimRig("--finger 1 --quick --compensator pi:32 --allow-fallback --out " + dir));
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "compensator none: the static inverse alone (--allow-fallback)"));
  std::ifstream file(dir + "/PN-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  CHECK(j["compensator"]["kind"] == "none");
  CHECK(j["quality"]["flags"].dump().find("compensator not fitted: sweep has 53 points; this fit "
                                          "needs at least 68") != std::string::npos);
}

TEST(CliCalibrate, AFitThatFailsAfterTheRunExits1AndKeepsTheJournal) {
  // A journal holding the whole quick sweep, one reading's drive past the range (as a sensor out
  // of calibration could read it): resumed, the run measures nothing more and the fit refuses it.
  const std::string dir = MakeTempDir("palpa-cal-cli");
  nlohmann::json sweep = nlohmann::json::array();
  for (const double pa :
       palpa::calibration::SweepDrives(palpa::calibration::QuickProtocol().pneumatic_sweep)) {
    sweep.push_back({pa, 0.01 * pa});  // µm
  }
  sweep[29][0] = 110000.0;
  const std::string journal = dir + "/PN-1.journal.json";
  std::ofstream(journal) << nlohmann::json{{"sweep", sweep}}.dump();
  Run r = Palpa("calibrate --rig sim --finger 1 --quick --compensator pi:8 --resume --out " + dir);
  LONGS_EQUAL_TEXT(1, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "the compensator could not be fitted: sweep point 29: drive 110000"),
             r.output.c_str());
  CHECK(access((dir + "/PN-1.json").c_str(), F_OK) != 0);  // nothing written
  CHECK(access(journal.c_str(), F_OK) == 0);               // the measurements kept
  // Allowed to fall back, the same journal gives the static inverse alone.
  r = Palpa(
      "calibrate --rig sim --finger 1 --quick --compensator pi:8 --resume --allow-fallback "
      "--out " +
      dir);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  std::ifstream file(dir + "/PN-1.json");
  CHECK(nlohmann::json::parse(file)["compensator"]["kind"] == "none");
  std::filesystem::remove_all(dir);
}

TEST_GROUP(CliCalibrateQuick){};

TEST(CliCalibrateQuick, QuickCalibrationOnTheSimulatedRigWritesAValidFileRawDataAndAReport) {
  const std::string dir = MakeTempDir("palpa-cal-cli");
  const Run r = Palpa(OnTheSimRig("--finger 1 --quick --apply --out " + dir));
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "calibrated PN-1"));
  CHECK(Has(r, "applied to finger 1"));
  std::ifstream file(dir + "/PN-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  // Left to choose, calibration fits both play models, keeps one and says what it compared (with
  // the rig's 2.82 % repeatability most of either residual is scatter, so it may keep pi).
  CHECK(j["compensator"]["kind"] == "api" || j["compensator"]["kind"] == "pi");
  CHECK_TEXT(Has(r, "model chosen (auto): ") && Has(r, "api(8) ") && Has(r, "pi(8)"),
             r.output.c_str());
  CHECK(j["static_inverse"].size() >= 8);
  const std::string report = FileText(dir + "/PN-1.html");
  CHECK(report.find("<svg") != std::string::npos);
  CHECK(report.find("Regulator static correction") != std::string::npos);
  CHECK(access((dir + "/PN-1.journal.json").c_str(), F_OK) !=
        0);  // a finished run leaves no journal
}

TEST_GROUP(CliCalibrateAdaptive){};

TEST(CliCalibrateAdaptive, AdaptiveMapOnAJammingFingerReportsItsChecks) {
  const std::string dir = MakeTempDir("palpa-cal-cli");
  const Run r =
      Palpa(OnTheSimRig("--finger 4 --quick --protocol adaptive --max-cycles 8 --out " + dir));
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "stiffness map: adaptive, 8 cycles"));
  for (const char* check : {"check points", "check noise", "check force_zero", "check leak"})
    CHECK_TEXT(Has(r, check), check);
  std::ifstream file(dir + "/JAM-1.json");
  const nlohmann::json j = nlohmann::json::parse(file);
  CHECK(j["quality"]["protocol"] == "adaptive");
  LONGS_EQUAL(4, j["quality"]["checks"].size());
  const std::string report = FileText(dir + "/JAM-1.html");
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
