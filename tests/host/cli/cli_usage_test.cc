// The palpa command line refusing what it cannot run: exit codes, each mistake named with what
// was meant, JSON errors under --json, and nothing sent on a bad command line.
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"
#include "palpa/host/stimulus_set.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::kNowhere;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP(CliUsage){};

TEST(CliUsage, HelpForEveryCommand) {
  for (const char* command : {"list", "info", "diag", "config", "set", "line", "monitor", "record",
                              "estop", "clear", "demo", "calibrate", "flash", "package", "sim"}) {
    const Run r = Palpa(std::string(command) + " --help");
    LONGS_EQUAL_TEXT(0, r.code, command);
    CHECK_TEXT(Has(r, "usage: palpa"), command);
  }
  CHECK(Has(Palpa("--help"), "Exit codes"));
}

TEST(CliUsage, MalformedCommandLinesNameTheArgumentAndSendNothing) {
  // The device does not exist: a usage error must come before any attempt to open it.
  Run r = ExpectUsage(kNowhere + "set 1=L2x", "'1=L2x'");
  r = ExpectUsage(kNowhere + "set 0=L1", "finger must be a whole number from 1");
  r = ExpectUsage(kNowhere + "set 2=1.7", "normalised stiffness from 0 to 1");
  r = Palpa(kNowhere + "set 4=0.9N/m");
  LONGS_EQUAL(2, r.code);
  r = ExpectUsage(kNowhere + "line 1=abc", "'1=abc'");
  r = ExpectUsage(kNowhere + "monitor --rate fast", "--rate");
  r = ExpectUsage(kNowhere + "record out.csv", "--duration");
  r = ExpectUsage(kNowhere + "frobnicate", "unknown command 'frobnicate'");
  r = Palpa("--device");
  LONGS_EQUAL(2, r.code);
  // The demo's chart is written at its end: a place it cannot be written is refused first.
  r = ExpectUsage("demo --out /nonexistent-dir/chart.svg", "/nonexistent-dir is not a directory");
  CHECK_FALSE(Has(r, "starting a simulated"));
  r = ExpectUsage("demo --out", "--out needs a file name");
  r = ExpectUsage("demo --out /tmp/chart.png", "give a name ending in .svg");
  r = ExpectUsage("demo --speed 20", "--speed needs a number from 0.1 to 10");
  r = ExpectUsage("demo --calibration /nonexistent-dir",
                  "--calibration /nonexistent-dir: not a directory");
  r = ExpectUsage("demo --nominal-only --calibration /tmp", "exclude each other");
  // Stimulus sets: by name or file, the bad field named, the right fingers for the board.
  r = ExpectUsage("demo --stimuli", "--stimuli needs");
  r = ExpectUsage("demo --stimuli thesis-pneumatic-15", "no stimulus set \"thesis-pneumatic-15\"");
  const std::string set_file = OwnTempPath("set.json");
  {
    std::string text = palpa::host::ShippedStimulusSetText("thesis-pneumatic-14");
    text.replace(text.find("\"L2\""), 4, "\"L9\"");  // the level's name, not the stimuli's
    std::ofstream(set_file) << text;
  }
  r = ExpectUsage("demo --stimuli " + set_file, "stimuli[2].levels[0]: \"L2\" is not a level");
  {
    std::string text = palpa::host::ShippedStimulusSetText("thesis-pneumatic-14");
    const std::string marked = "\"tumour\": [\n        2";
    text.replace(text.find(marked) + marked.size() - 1, 1, "1");
    std::ofstream(set_file) << text;
  }
  r = ExpectUsage("demo --stimuli " + set_file, "is not what the rule gives");
  std::ofstream(set_file) << R"({"schema": "palpa-stimuli", "schema_version": 1, "name": "two",
    "description": "d", "finger_kind": "pneumatic", "fingers": 2,
    "levels": [{"name": "a", "kpa": 0}, {"name": "b", "kpa": 5}], "rule": "tumour",
    "conditions": ["multi-finger"], "selection": {"how": "x"},
    "stimuli": [{"levels": ["a", "b"], "tumour": [2]}]})";
  r = ExpectUsage("demo --stimuli " + set_file,
                  "a set for 2 pneumatic fingers; the demo's board has 3");
  std::remove(set_file.c_str());
  const std::string bad = OwnTempPath("bad.json");
  std::ofstream(bad) << "{\"board\": {\"host_timeout_us\": 1e3.5}";
  r = Palpa(kNowhere + "config load " + bad);
  std::remove(bad.c_str());
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "not valid JSON"));
}

TEST(CliUsage, MistakesAreNamedWithWhatWasMeant) {
  ExpectUsage(kNowhere + "sett 1=L2", "unknown command 'sett' (did you mean 'set'?)");
  ExpectUsage(kNowhere + "monitr", "did you mean 'monitor'?");
  ExpectUsage(kNowhere + "config shwo", "did you mean 'show'?");
  ExpectUsage("--jsn info", "unknown option '--jsn' (did you mean --json?)");
  ExpectUsage(kNowhere + "set 1=10kpa", "'1=10kpa': unknown unit 'kpa' (did you mean 10kPa?)");
  ExpectUsage(kNowhere + "set 3=1.2MM", "did you mean 1.2mm?");
  ExpectUsage(kNowhere + "set 4=0.9n/mm", "did you mean 0.9N/mm?");
  ExpectUsage(kNowhere + "line 6=-40KPA", "did you mean -40kPa?");
  // The same finger twice: which one was meant? Nothing is sent.
  ExpectUsage(kNowhere + "set 1=L2 1=L1", "finger 1 is given twice ('1=L2' and '1=L1')");
  ExpectUsage(kNowhere + "line 2=10 2=20", "line 2 is given twice");
  // strtod's other numbers are not numbers here.
  ExpectUsage(kNowhere + "set 1=0x1", "'1=0x1': expected L<level>");
  ExpectUsage(kNowhere + "set 0x1=L1", "finger must be a whole number");
  ExpectUsage(kNowhere + "set 2=inf", "'2=inf'");
  ExpectUsage(kNowhere + "line 1=nan", "'1=nan'");
  ExpectUsage(kNowhere + "set 1=L0x2", "a level is L followed by");
  // An option whose value is missing says so, even when another option follows.
  ExpectUsage(kNowhere + "monitor --duration", "--duration: a value is missing");
  ExpectUsage(kNowhere + "monitor --rate --duration 1", "--rate: a value is missing");
  ExpectUsage(kNowhere + "set 1=L1 --hold", "--hold: a value is missing");
  ExpectUsage("--device", "--device: a value is missing");
}

TEST(CliUsage, JsonErrorsAreJson) {
  // With --json every outcome is a JSON document on stdout, a refusal too.
  auto error_of = [](const std::string& args, int code) {
    const Run r = Palpa("--json " + args, "", false);
    LONGS_EQUAL_TEXT(code, r.code, r.output.c_str());
    const auto j = nlohmann::json::parse(r.output);
    LONGS_EQUAL(code, j["error"]["exit_code"].get<int>());
    return j["error"];
  };
  auto e = error_of("--device tcp:127.0.0.1:1 set 1=L2x", 2);
  STRCMP_EQUAL("invalid_argument", e["status"].get<std::string>().c_str());
  CHECK(e["message"].get<std::string>().find("'1=L2x'") != std::string::npos);
  STRCMP_EQUAL("set", e["command"].get<std::string>().c_str());
  e = error_of("--device tcp:127.0.0.1:1 info", 3);
  STRCMP_EQUAL("unavailable", e["status"].get<std::string>().c_str());
  e = error_of("frobnicate", 2);
  CHECK(e["message"].get<std::string>().find("frobnicate") != std::string::npos);
  e = error_of("demo --out chart.png", 2);
  CHECK(e["message"].get<std::string>().find(".svg") != std::string::npos);
}

TEST(CliUsage, UnreachableDeviceIsExitCodeThree) {
  const Run r = Palpa("--device tcp:127.0.0.1:1 info");
  LONGS_EQUAL(3, r.code);
  CHECK(Has(r, "tcp:127.0.0.1:1"));
}
