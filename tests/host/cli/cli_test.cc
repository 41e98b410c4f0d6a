// The palpa command line as a person uses it: exit codes, named errors, nothing sent on a bad
// command line, and the commands against palpa-sim.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "mini_client.h"
#include "palpa/calibration/calibration_protocol.h"

#include "palpa/host/stimulus_set.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::ExpectUsage;
const std::string kDevelopmentKey = PALPA_DEVELOPMENT_KEY;  // DEVELOPMENT ONLY
using palpa::testing::Has;
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
  const std::string nowhere = "--device tcp:127.0.0.1:1 ";
  Run r = ExpectUsage(nowhere + "set 1=L2x", "'1=L2x'");
  r = ExpectUsage(nowhere + "set 0=L1", "finger must be a whole number from 1");
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
  r = Palpa(nowhere + "config load " + bad);
  std::remove(bad.c_str());
  LONGS_EQUAL(2, r.code);
  CHECK(Has(r, "not valid JSON"));
}

TEST(CliUsage, MistakesAreNamedWithWhatWasMeant) {
  const std::string nowhere = "--device tcp:127.0.0.1:1 ";
  ExpectUsage(nowhere + "sett 1=L2", "unknown command 'sett' (did you mean 'set'?)");
  ExpectUsage(nowhere + "monitr", "did you mean 'monitor'?");
  ExpectUsage(nowhere + "config shwo", "did you mean 'show'?");
  ExpectUsage("--jsn info", "unknown option '--jsn' (did you mean --json?)");
  ExpectUsage(nowhere + "set 1=10kpa", "'1=10kpa': unknown unit 'kpa' (did you mean 10kPa?)");
  ExpectUsage(nowhere + "set 3=1.2MM", "did you mean 1.2mm?");
  ExpectUsage(nowhere + "set 4=0.9n/mm", "did you mean 0.9N/mm?");
  ExpectUsage(nowhere + "line 6=-40KPA", "did you mean -40kPa?");
  // The same finger twice: which one was meant? Nothing is sent.
  ExpectUsage(nowhere + "set 1=L2 1=L1", "finger 1 is given twice ('1=L2' and '1=L1')");
  ExpectUsage(nowhere + "line 2=10 2=20", "line 2 is given twice");
  // strtod's other numbers are not numbers here.
  ExpectUsage(nowhere + "set 1=0x1", "'1=0x1': expected L<level>");
  ExpectUsage(nowhere + "set 0x1=L1", "finger must be a whole number");
  ExpectUsage(nowhere + "set 2=inf", "'2=inf'");
  ExpectUsage(nowhere + "line 1=nan", "'1=nan'");
  ExpectUsage(nowhere + "set 1=L0x2", "a level is L followed by");
  // An option whose value is missing says so, even when another option follows.
  ExpectUsage(nowhere + "monitor --duration", "--duration: a value is missing");
  ExpectUsage(nowhere + "monitor --rate --duration 1", "--rate: a value is missing");
  ExpectUsage(nowhere + "set 1=L1 --hold", "--hold: a value is missing");
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
  // One numbering for what a person reads: from 1, and no line is null, not 0 or 255.
  LONGS_EQUAL(1, j["fingers"][0]["finger"].get<int>());
  LONGS_EQUAL(1, j["fingers"][0]["line_a"].get<int>());
  CHECK(j["fingers"][0]["line_b"].is_null());
  LONGS_EQUAL(6, j["fingers"][3]["line_b"].get<int>());
  LONGS_EQUAL(1, j["lines"][0]["line"].get<int>());
  STRCMP_EQUAL("N/mm", j["fingers"][3]["unit"].get<std::string>().c_str());
  r = Palpa(device + "info");
  CHECK(Has(r, "finger 4      jamming"));
  CHECK(Has(r, "line 1, second line none"));
  r = Palpa(device + "--json diag");
  LONGS_EQUAL(0, r.code);
  CHECK(nlohmann::json::parse(r.output).contains("loop"));
}

TEST(CliBoard, SetChecksUnitsPerFingerKind) {
  Run r = Palpa(device + "set 1=L2 2=0.5 3=1.2mm 4=0.9N/mm 5=-10kPa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "nominal thesis curves"));
  // Uncalibrated, the notes say what the nominal curves stand on: the bare film, an axis range.
  CHECK_TEXT(Has(r, "Table 5-4's bare film without the top layer"), r.output.c_str());
  CHECK_TEXT(Has(r, "Fig 5-36(c)'s axis range, an assumption"), r.output.c_str());
  r = Palpa(device + "set 1=0.9N/mm");
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "N/mm means nothing for a pneumatic finger"));
  r = Palpa(device + "set 4=2.0N/mm");
  LONGS_EQUAL(1, r.code);
  // No calibration is loaded: the range is the nominal curve's, and says so — Fig 5-36(c)'s axis,
  // an assumption.
  CHECK_TEXT(Has(r, "outside the nominal curve's range (Fig 5-36(c)'s axis range, an assumption"),
             r.output.c_str());
  CHECK_TEXT(Has(r, "calibrated) 0.7 … 1.3"), r.output.c_str());
  CHECK_FALSE(Has(r, "calibrated range"));
  // A finger this board does not have: its own range, not the protocol's.
  r = ExpectUsage(device + "set 9=L1", "finger 9: this thesis-5finger board has fingers 1 to 5");
  r = ExpectUsage(device + "set 6=L1", "has fingers 1 to 5");
  r = ExpectUsage(device + "line 8=10", "line 8: this thesis-5finger board has lines 1 to 7");
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
  // The argument is named once, with its own line number, and the fields there are listed.
  r = ExpectUsage(device + "config set line2.slew=5",
                  "'line2.slew=5': unknown field 'slew' (the fields: ");
  CHECK(Has(r, "slew_pa_per_s"));
  CHECK_FALSE(Has(r, "lines[0]"));
  LONGS_EQUAL(std::string::npos, r.output.find("'slew'", r.output.find("'slew'") + 1));
  r = ExpectUsage(device + "config set line9.slew_pa_per_s=5", "this board has lines 1 to 7");
  r = ExpectUsage(device + "config set finger1.finger=2", "the entry's number");
  // config show is a configuration file: numbered from 0 as on the wire, and says so; a finger
  // without a second line has none (null), not 255.
  r = Palpa(device + "--json config show");
  const auto shown = nlohmann::json::parse(r.output);
  STRCMP_EQUAL("from 0, as on the wire", shown["numbering"].get<std::string>().c_str());
  LONGS_EQUAL(0, shown["fingers"][0]["finger"].get<int>());
  CHECK(shown["fingers"][0]["line_b"].is_null());
}

TEST(CliBoard, InfoSaysWhetherTheConfigurationIsSaved) {
  auto state = [&] {
    const Run r = Palpa(device + "info");
    const size_t at = r.output.find("configuration ");
    return r.output.substr(at, r.output.find('\n', at) - at);
  };
  STRCMP_EQUAL("configuration thesis-5finger (factory default)", state().c_str());
  LONGS_EQUAL(0, Palpa(device + "config set board.host_timeout_us=200000").code);
  STRCMP_EQUAL(
      "configuration thesis-5finger (changed, not saved: a reset returns to the factory default)",
      state().c_str());
  Run r = Palpa(device + "config save");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  STRCMP_EQUAL("configuration thesis-5finger (saved)", state().c_str());
  LONGS_EQUAL(0, Palpa(device + "config set board.host_timeout_us=300000").code);
  STRCMP_EQUAL(
      "configuration thesis-5finger (changed, not saved: a reset returns to the saved one)",
      state().c_str());
  LONGS_EQUAL(0, Palpa(device + "config factory-reset").code);
  LONGS_EQUAL(0, Palpa(device + "set 1=L1").code);
  STRCMP_EQUAL("configuration thesis-5finger (factory default)", state().c_str());
}

TEST(CliBoard, SetSaysWhatWasApplied) {
  Run r = Palpa(device + "set 1=L2 4=0.9N/mm 5=-10kPa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "finger 1: level 2 = 30 kPa → target 1.164 mm"), r.output.c_str());
  CHECK(Has(r, "finger 4: 0.9 N/mm → target 0.900 N/mm"));
  CHECK(Has(r, "finger 5: -10 kPa → line 5 at 20.0 kPa, line 7 at -10.0 kPa (raw"));
  r = Palpa(device + "--json set 1=L2 2=0.5 5=-10kPa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const auto j = nlohmann::json::parse(r.output);
  const auto& first = j["applied"][0];
  LONGS_EQUAL(1, first["finger"].get<int>());
  STRCMP_EQUAL("target", first["mode"].get<std::string>().c_str());
  DOUBLES_EQUAL(30, first["level_kpa"].get<double>(), 1e-9);
  DOUBLES_EQUAL(1.164, first["target"]["value"].get<double>(), 0.001);
  STRCMP_EQUAL("mm", first["target"]["unit"].get<std::string>().c_str());
  CHECK(first["map"].get<std::string>().find("nominal thesis curves") != std::string::npos);
  const auto& raw = j["applied"][2];
  STRCMP_EQUAL("raw", raw["mode"].get<std::string>().c_str());
  LONGS_EQUAL(7, raw["setpoints"][1]["line"].get<int>());
  DOUBLES_EQUAL(-10, raw["setpoints"][1]["kpa"].get<double>(), 1e-9);
}

TEST(CliBoard, EveryCommandSpeaksJson) {
  const std::string recording = OwnTempPath("json.csv");
  for (const std::string& command :
       {std::string("info"), std::string("diag"), std::string("config show"),
        std::string("config set board.telemetry_batch=2"), std::string("set 1=L1"),
        std::string("line 1=5"), std::string("estop"), std::string("clear"), std::string("list"),
        std::string("monitor --duration 0.3"), "record " + recording + " --duration 0.2",
        std::string("sim status")}) {
    const Run r = Palpa(device + "--json " + command);
    LONGS_EQUAL_TEXT(0, r.code, (command + ": " + r.output).c_str());
    size_t at = 0;
    while (at < r.output.size()) {  // monitor: one document per line
      const size_t end = r.output.find('\n', at);
      const std::string line = r.output.substr(at, end - at);
      CHECK_TEXT(nlohmann::json::accept(line), (command + ": " + line).c_str());
      at = end == std::string::npos ? r.output.size() : end + 1;
    }
  }
  std::remove(recording.c_str());
}

TEST(CliBoard, MonitorRecordEstopClear) {
  Run r = Palpa(device + "--json monitor --rate 50 --duration 0.5");
  LONGS_EQUAL(0, r.code);
  const auto first = nlohmann::json::parse(r.output.substr(0, r.output.find('\n')));
  LONGS_EQUAL(7, first["lines"].size());
  LONGS_EQUAL(1, first["lines"][0]["line"].get<int>());
  // Each finger's output in its unit, not only the lines' pressures.
  LONGS_EQUAL(5, first["fingers"].size());
  STRCMP_EQUAL("mm", first["fingers"][0]["unit"].get<std::string>().c_str());
  STRCMP_EQUAL("N/mm", first["fingers"][4]["unit"].get<std::string>().c_str());
  DOUBLES_EQUAL(0.7, first["fingers"][4]["output"].get<double>(), 0.05);  // released
  r = Palpa(device + "monitor --duration 0.3");
  CHECK(Has(r, "finger  kind       output"));
  CHECK(Has(r, "jamming     0.7"));
  // The board sends 1000 samples a second: more is refused, naming that.
  r = ExpectUsage(device + "monitor --rate 5000 --duration 1",
                  "the board sends 1000 samples a second");

  LONGS_EQUAL(0, Palpa(device + "clear").code);
  r = Palpa(device + "clear");  // nothing latched: says so rather than "cleared"
  CHECK_TEXT(Has(r, "no faults were latched"), r.output.c_str());
  LONGS_EQUAL(0, Palpa(device + "estop").code);
  r = Palpa(device + "--json diag");
  CHECK(nlohmann::json::parse(r.output)["faults_latched"].get<int>() != 0);
  r = Palpa(device + "clear");
  LONGS_EQUAL(0, r.code);
  CHECK(Has(r, "faults cleared: estop_command"));
}

namespace {

/// A recording's header (JSON), column names and rows.
struct Recording {
  nlohmann::json header;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  size_t at = 0;
  for (size_t comma; (comma = line.find(',', at)) != std::string::npos; at = comma + 1)
    cells.push_back(line.substr(at, comma - at));
  cells.push_back(line.substr(at));
  return cells;
}

Recording ReadRecording(const std::string& path) {
  std::ifstream in(path);
  Recording r;
  std::string line;
  std::getline(in, line);
  r.header = nlohmann::json::parse(line.substr(2));
  std::getline(in, line);
  r.columns = Cells(line);
  while (std::getline(in, line)) r.rows.push_back(Cells(line));
  return r;
}

}  // namespace

TEST(CliBoard, RecordingsCarryUtcAndBoardTimeAColumnPerLineAndFingerAndNamedBits) {
  const std::string path = OwnTempPath("wide.csv");
  const time_t before = time(nullptr);
  Run r = Palpa(device + "record " + path + " --duration 0.5");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const Recording wide = ReadRecording(path);
  std::remove(path.c_str());
  STRCMP_EQUAL("palpa recording 2", wide.header["format"].get<std::string>().c_str());
  CHECK(wide.header.dump().find("e+300") == std::string::npos);
  CHECK(wide.header["numbering"].get<std::string>().find("from 1") != std::string::npos);
  // A row per sample: UTC, board time, faults, four columns a line, a column a finger.
  const std::vector<std::string> expected_start = {
      "utc_time",          "board_time_us",        "faults",      "line1_setpoint_pa",
      "line1_measured_pa", "line1_command_counts", "line1_status"};
  CHECK(std::equal(expected_start.begin(), expected_start.end(), wide.columns.begin()));
  LONGS_EQUAL(3 + 7 * 4 + 5, wide.columns.size());
  STRCMP_EQUAL("finger1_mm", wide.columns[3 + 28].c_str());
  STRCMP_EQUAL("finger5_n_per_mm", wide.columns.back().c_str());
  CHECK(wide.rows.size() > 300);  // 1 kHz for about half a second
  for (const auto& row : {wide.rows.front(), wide.rows.back()}) {
    LONGS_EQUAL(wide.columns.size(), row.size());
    // UTC wall time, now: not seconds since the board or the host booted.
    std::tm utc{};
    CHECK_TEXT(strptime(row[0].c_str(), "%Y-%m-%dT%H:%M:%S", &utc) != nullptr, row[0].c_str());
    CHECK_TEXT(row[0].back() == 'Z', row[0].c_str());
    const time_t at = timegm(&utc);
    CHECK_TEXT(at >= before - 1 && at <= time(nullptr) + 1, row[0].c_str());
    STRCMP_EQUAL("none", row[2].c_str());
    CHECK_TEXT(row[6].find("safe") == 0, row[6].c_str());  // status by name
  }
  CHECK(std::stoull(wide.rows.back()[1]) > std::stoull(wide.rows.front()[1]));

  // The long layout stays: a row per line per sample, lines numbered from 1.
  r = Palpa(device + "record " + path + " --duration 0.3 --long");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const Recording long_layout = ReadRecording(path);
  std::remove(path.c_str());
  const std::vector<std::string> long_columns = {"utc_time",    "board_time_us", "line",
                                                 "setpoint_pa", "measured_pa",   "command_counts",
                                                 "status",      "faults"};
  CHECK(long_layout.columns == long_columns);
  STRCMP_EQUAL("1", long_layout.rows.front()[2].c_str());
  STRCMP_EQUAL("7", long_layout.rows[6][2].c_str());
}

TEST_GROUP(CliSim) {
  std::string state, env;
  void setup() override {
    char pattern[] = "/tmp/palpa-cli-state-XXXXXX";
    state = mkdtemp(pattern);
    env = "PALPA_STATE_DIR=" + state + " ";
  }
  void teardown() override {
    Palpa("sim stop", env);
    std::system(("rm -rf " + state).c_str());
  }
};

TEST(CliSim, WithoutAKeptBoardEachCommandSaysItRanOnAThrowawayOne) {
  Run r = Palpa("estop", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "this ran on a throwaway simulated board (sim:thesis-5finger)"),
             r.output.c_str());
  CHECK(Has(r, "'palpa sim start' keeps one board running"));
  r = Palpa("clear", env);  // another board: nothing to clear, and it says so
  CHECK_TEXT(Has(r, "no faults were latched"), r.output.c_str());
  CHECK(Has(r, "throwaway"));
  r = Palpa("sim status", env);
  CHECK(Has(r, "no simulated board is running"));
}

TEST(CliSim, AKeptBoardLivesAcrossCommandsAndItsFlashAcrossRestarts) {
  Run r = Palpa("sim start", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "simulated thesis-5finger board running"));
  r = Palpa("sim start", env);  // one at a time
  LONGS_EQUAL(1, r.code);
  CHECK(Has(r, "already running"));
  // estop then clear: the same board, so the clear finds the EStop latched.
  r = Palpa("estop", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_FALSE(Has(r, "throwaway"));
  r = Palpa("clear", env);
  CHECK_TEXT(Has(r, "faults cleared: estop_command"), r.output.c_str());
  // A configuration set in one command is there in the next, and once saved after a restart.
  LONGS_EQUAL(0, Palpa("config set board.host_timeout_us=200000", env).code);
  r = Palpa("--json config show", env);
  LONGS_EQUAL(200000, nlohmann::json::parse(r.output)["board"]["host_timeout_us"].get<int>());
  r = Palpa("config save", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("sim stop", env);
  CHECK_TEXT(Has(r, "its flash stays in " + state + "/sim-thesis-5finger.flash"), r.output.c_str());
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  r = Palpa("info", env);
  CHECK_TEXT(Has(r, "configuration thesis-5finger (saved)"), r.output.c_str());
  r = Palpa("--json config show", env);
  LONGS_EQUAL(200000, nlohmann::json::parse(r.output)["board"]["host_timeout_us"].get<int>());
  r = Palpa("--json sim status", env);
  const auto status = nlohmann::json::parse(r.output);
  CHECK(status["running"].get<bool>());
  STRCMP_EQUAL("thesis-5finger", status["config"].get<std::string>().c_str());

  // The firmware slots and boot state are in the same flash: an update survives a restart.
  std::ofstream(state + "/a.bin") << std::string(20000, 'a');
  std::ofstream(state + "/b.bin") << std::string(20000, 'b');
  r = Palpa("package " + state + "/a.bin " + state + "/b.bin --version 0.3.0 --counter 2 --sign " +
                kDevelopmentKey + " --out " + state + "/new.palpa",
            env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = Palpa("flash " + state + "/new.palpa", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  LONGS_EQUAL(0, Palpa("sim stop", env).code);
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  r = Palpa("info", env);
  CHECK_TEXT(Has(r, "firmware      0.3.0"), r.output.c_str());
  CHECK(Has(r, "image slot    1, anti-rollback counter 2"));

  // A flash file belongs to one configuration.
  LONGS_EQUAL(0, Palpa("sim stop", env).code);
  r = Palpa("sim start --config thesis-pneumatic-3 --flash " + state + "/sim-thesis-5finger.flash",
            env);
  LONGS_EQUAL(1, r.code);
  CHECK_TEXT(Has(r, "the flash of a thesis-5finger board, not of a thesis-pneumatic-3 one"),
             r.output.c_str());
  r = Palpa("sim stop", env);
  CHECK(Has(r, "no simulated board is running"));
}

TEST(CliSim, ARecordWhoseBoardIsGoneIsNotUsed) {
  LONGS_EQUAL(0, Palpa("sim start", env).code);
  const auto status = nlohmann::json::parse(Palpa("--json sim status", env).output);
  kill(status["pid"].get<int>(), SIGKILL);
  for (int i = 0; i < 100 && kill(status["pid"].get<int>(), 0) == 0; ++i) usleep(20000);
  const Run r = Palpa("info", env);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "no longer running"));
  CHECK(Has(r, "throwaway"));
}

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
  // The rig's simulator: its options are checked here, go with --rig sim only, and an
  // environment variable it would not read is refused rather than ignored.
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --unit 1001",
                  "--unit 1001: expected an actuator unit 0 to 1000");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --plant 2.5",
                  "--plant 2.5: expected a plant level 0 to 3");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --effects creep,wind",
                  "--effects creep,wind: unknown effect 'wind'");
  r = ExpectUsage(nowhere + "calibrate --rig sim --finger 1 --out /tmp --effects history=0.9",
                  "history wants a fraction of 0 to 0.5");
  r = ExpectUsage(nowhere + "calibrate --rig lab.json --finger 1 --out /tmp --unit 2",
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
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const Run r =
      Palpa("calibrate --rig sim --finger 1 --quick --speed 10 --unit 12 --seed 3 --out " + dir);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "calibrated PN-1 (finger 1, simulated unit 12, seed 3, plant level 3)"),
             r.output.c_str());
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
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
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
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
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
  std::system(("rm -rf " + dir).c_str());
}

TEST_GROUP(CliCalibrateQuick){};

TEST(CliCalibrateQuick, QuickCalibrationOnTheSimulatedRigWritesAValidFileRawDataAndAReport) {
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
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
  std::ifstream html(dir + "/PN-1.html");
  std::string report((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  CHECK(report.find("<svg") != std::string::npos);
  CHECK(report.find("Regulator static correction") != std::string::npos);
  CHECK(access((dir + "/PN-1.journal.json").c_str(), F_OK) !=
        0);  // a finished run leaves no journal
}

TEST_GROUP(CliCalibrateAdaptive){};

TEST(CliCalibrateAdaptive, AdaptiveMapOnAJammingFingerReportsItsChecks) {
  char pattern[] = "/tmp/palpa-cal-cli-XXXXXX";
  const std::string dir = mkdtemp(pattern);
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
  const auto package = [&](const std::string& version, const std::string& counter,
                           const std::string& key, const std::string& name) {
    return Palpa("package " + dir + "/a.bin " + dir + "/b.bin --version " + version +
                 " --counter " + counter + " --sign " + key + " --out " + dir + "/" + name);
  };
  Run r = package("0.3.0", "2", kDevelopmentKey, "new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "signed by key "), r.output.c_str());
  LONGS_EQUAL(0, package("0.0.9", "0", kDevelopmentKey, "old.palpa").code);
  LONGS_EQUAL(0, package("0.2.0", "2", kDevelopmentKey, "down.palpa").code);
  // The review's attack: a package that would pin the board's counter at its maximum.
  LONGS_EQUAL(0, package("9.9.9", "4294967295", kDevelopmentKey, "pin.palpa").code);
  // Signed by a key of this lab's own, which the development board does not trust.
  const std::string lab = dir + "/lab.key";
  r = Palpa("keygen " + lab);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  LONGS_EQUAL(0, package("0.4.0", "2", lab, "lab.palpa").code);
  std::ofstream(dir + "/lab.key.pub2") << "# not a key\nhello\n";
  r = ExpectUsage("package " + dir + "/a.bin " + dir + "/b.bin --version 1.0.0 --counter 1 --out " +
                      dir + "/unsigned.palpa",
                  "--sign KEY");
  r = ExpectUsage("package " + dir + "/a.bin " + dir +
                      "/b.bin --version 1.0.0 --counter 1 --sign " + dir + "/lab.key.pub2 --out " +
                      dir + "/x.palpa",
                  "not a private key file");
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
  CHECK_TEXT(Has(r, "anti-rollback counter 2 (board's floor 1), signed by key "), r.output.c_str());
  // The counter jump is flagged before anything is written (the dry run says so too).
  r = ExpectUsage(device + "flash " + dir + "/pin.palpa --dry-run", "jumps from the board's 1");
  r = ExpectUsage(device + "flash " + dir + "/pin.palpa", "--allow-counter-jump");
  CHECK(Has(r, "Nothing was written"));
  // The board itself refuses an image its keys did not sign, at activation.
  r = Palpa(device + "flash " + dir + "/lab.palpa");
  LONGS_EQUAL_TEXT(2, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "signed by a key this board does not trust"), r.output.c_str());
  r = Palpa(device + "flash " + dir + "/new.palpa");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "updated 0.1.0 → 0.3.0 (slot 1), confirmed"));
  r = Palpa(device + "info");
  CHECK(Has(r, "firmware      0.3.0"));
  CHECK(Has(r, "image slot    1, anti-rollback counter 2"));
  r = ExpectUsage(device + "flash " + dir + "/old.palpa",
                  "anti-rollback counter 0 is below the board's 2");
  // A lower version at the same counter: only when asked for.
  r = ExpectUsage(device + "flash " + dir + "/down.palpa",
                  "0.2.0 is older than the running 0.3.0 at the same anti-rollback counter 2");
  r = Palpa(device + "flash " + dir + "/down.palpa --allow-downgrade");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK(Has(r, "updated 0.3.0 → 0.2.0 (slot 0), confirmed"));
}

TEST(CliFlash, KeygenWritesAPrivateKeyOnlyItsOwnerReadsAndNeverOverwrites) {
  char pattern[] = "/tmp/palpa-keygen-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const std::string key = dir + "/release.key";
  Run r = Palpa("keygen " + key);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "(mode 0600: keep it secret)"), r.output.c_str());
  struct stat st {};
  LONGS_EQUAL(0, stat(key.c_str(), &st));
  LONGS_EQUAL(0600, st.st_mode & 0777);
  std::ifstream in(key);
  const std::string before((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  r = ExpectUsage("keygen " + key, "exists; not overwritten");
  std::ifstream again(key);
  const std::string after((std::istreambuf_iterator<char>(again)),
                          std::istreambuf_iterator<char>());
  CHECK(before == after);
  r = Palpa("--json keygen " + dir + "/second.key");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  const auto json = nlohmann::json::parse(r.output);
  LONGS_EQUAL(16, json["key_id"].get<std::string>().size());
  r = ExpectUsage("keygen", "needs one FILE");
  std::system(("rm -rf " + dir).c_str());
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
  // Its millimetres say whose they are: Table 5-4's film, without the top layer.
  CHECK(Has(r, "Deformation is the bare film's"));
  CHECK(Has(r, "without the top silicone layer"));
  CHECK_TEXT(Has(r, "calibrated, api(8)"), r.output.c_str());
  const auto worst = SummaryRow(r, "pneumatic fingers: largest |error| / target");
  const auto gap = SummaryRow(r, "level 1 from above minus from below");
  // Nominal: the film's loop (0.18 against 0.36 mm at one target); calibrated: a few percent.
  CHECK_TEXT(worst.first > 30, r.output.c_str());
  CHECK_TEXT(worst.second >= 0 && worst.second < 10, r.output.c_str());
  CHECK_TEXT(gap.first > 100, r.output.c_str());
  CHECK_TEXT(std::fabs(gap.second) < 40, r.output.c_str());
}
