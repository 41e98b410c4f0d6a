// The palpa command line given hostile files: numbers JSON cannot hold, things that are not
// files, damaged journals and invalid calibrations — each a named error and an exit code, never
// an abort, a hang or a silent fallback.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::kNowhere;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliHostileFiles){};

TEST(CliHostileFiles, ConfigFilesNameTheFieldOfANumberJsonCannotHold) {
  const std::string file = OwnTempPath("huge.json");
  std::ofstream(file) << "{\"board\": {\"host_timeout_us\": 1e400}}";
  const Run r = ExpectUsage(kNowhere + "config load " + file, file + ": board.host_timeout_us: ");
  std::remove(file.c_str());
  CHECK_FALSE(Has(r, "[json.exception"));
  ExpectUsage(kNowhere + "config load /dev/null", "/dev/null: not a regular file");
}

TEST(CliHostileFiles, RigFilesNameTheFieldOfANumberJsonCannotHold) {
  const std::string rig = OwnTempPath("rig.json");
  std::ofstream(rig) << "{\"name\": \"lab\", \"force_noise_n\": 1e400}";
  ExpectUsage(kNowhere + "calibrate --rig " + rig + " --finger 1 --out /tmp",
              rig + ": force_noise_n: ");
  std::remove(rig.c_str());
}

TEST_GROUP_BASE(CliHostileBoard, palpa::testing::SimBoardGroup){};

TEST(CliHostileBoard, AnInvalidCalibrationIsNamedAndStrictModeRefusesIt) {
  const std::string file = dir + "/PN-1.json";
  std::ofstream(file) << "{\"schema\": \"palpa-calibration\", \"schema_version\": 7}";
  const std::string env = "PALPA_CALIBRATION_DIR=" + dir;
  Run r = palpa::testing::Palpa(device + "set 1=L1", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "nominal thesis curves (" + file + ": schema_version: 7 is not a version"),
             r.output.c_str());
  // With --json the same reason is in what set reports it applied: the map the finger went through.
  r = palpa::testing::Palpa(device + "--json set 1=L1", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const std::string map = nlohmann::json::parse(r.output)["applied"][0]["map"].get<std::string>();
  CHECK_TEXT(map.find("nominal thesis curves (" + file + ": schema_version: 7") == 0, map.c_str());
  r = palpa::testing::Palpa(device + "set --strict-calibration 2=L1 1=L1", env);
  LONGS_EQUAL_TEXT(1, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "finger 1: " + file + ": schema_version"), r.output.c_str());
  r = palpa::testing::Palpa(device + "--json set --strict-calibration 1=L1", env);
  LONGS_EQUAL_TEXT(1, r.code, r.output.c_str());
  const auto error = nlohmann::json::parse(r.output)["error"];
  STRCMP_EQUAL("bad_value", error["status"].get<std::string>().c_str());
  CHECK(error["message"].get<std::string>().find(file + ": schema_version") != std::string::npos);
  // A finger with no file at all is no error, strict or not.
  r = palpa::testing::Palpa(device + "set --strict-calibration 2=L1", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
}

TEST_GROUP(CliHostileJournal){};

TEST(CliHostileJournal, ADamagedJournalIsRefusedBeforeTheRigMoves) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-cli-journal");
  std::ofstream(dir + "/PN-1.journal.json") << "{\"sweep\": [[\"x\", 1]]}";
  const Run r = ExpectUsage("calibrate --rig sim --finger 1 --out " + dir + " --resume",
                            dir + "/PN-1.journal.json: sweep[0][0]: must be a number");
  CHECK_FALSE(Has(r, "zero on the vented surface"));
  std::filesystem::remove_all(dir);
}
