// The palpa commands against palpa-sim: info, diag, set, line, config, monitor, record, estop
// and clear, what each says and its JSON, and the recordings' layout.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_fixtures.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;
using palpa::testing::Run;

TEST_GROUP_BASE(CliBoard, palpa::testing::SimBoardGroup){};

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
