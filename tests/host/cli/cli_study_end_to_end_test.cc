// A study end to end: a shortened thesis-pneumatic with a staircase block run by `palpa study run`
// on simulated boards, answered by the simulated participant, then `palpa study report` over the
// sessions — its counts recounted here from the records themselves.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"

using nlohmann::json;
using palpa::testing::Palpa;
using palpa::testing::Shell;

namespace fs = std::filesystem;

namespace {

/// The built-in study as `study show` prints it, cut short: four of its fourteen conditions (no
/// tumour, one, another, two), one practice trial, short resets and presentations, and a
/// staircase block after the thesis's two.
json ShortenedThesisPneumatic() {
  const auto shown = Palpa("--json study show thesis-pneumatic", "", false);
  LONGS_EQUAL_TEXT(0, shown.code, shown.output.c_str());
  json s = json::parse(shown.output);
  const json all = s["conditions"];
  s["conditions"] = json::array({all[0], all[3], all[4], all[9]});
  s["reset"]["hold_ms"] = 300;
  for (json& b : s["blocks"]) {
    b["practice"] = 1;
    b.erase("break_every");
    if (b.contains("present_ms")) b["present_ms"] = 300;
  }
  s["blocks"].push_back(json::parse(R"({"name": "jnd", "kind": "staircase", "mode": "simultaneous",
      "staircase": {"reference": 10, "start": 16, "step": 1, "reversals": 3, "reversals_used": 2,
                    "max_trials": 16, "fingers": [1, 3]}})"));
  return s;
}

/// A CSV file as rows of fields (the report quotes no field these tests read).
std::vector<std::map<std::string, std::string>> Csv(const fs::path& path) {
  std::ifstream in(path);
  CHECK_TEXT(in.good(), path.c_str());
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    if (!line.empty() && line.back() == ',') fields.push_back("");
    if (header.empty()) {
      header = fields;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

struct Count {
  int trials = 0, tp = 0, fp = 0, tn = 0, fn = 0;
};

}  // namespace

TEST_GROUP(CliStudyEndToEnd){};

TEST(CliStudyEndToEnd, SimulatedParticipantsRunThenReported) {
  const fs::path root = palpa::testing::OwnTempPath("study-end-to-end");
  fs::remove_all(root);
  fs::create_directories(root);
  const fs::path file = root / "thesis-pneumatic-short.json";
  std::ofstream(file) << ShortenedThesisPneumatic().dump(2);
  const std::vector<std::string> who = {"P01", "P02", "P03"};
  // The three sessions at once, each on a simulated board of its own.
  std::string together;
  for (size_t p = 0; p < who.size(); ++p) {
    together += std::string("env -u PALPA_DEVICE PALPA_STATE_DIR=/nonexistent-palpa-state ") +
                PALPA_CLI_PATH + " study run " + file.string() + " --participant " + who[p] +
                " --out " + (root / who[p]).string() + " --speed 10 --simulated-participant " +
                std::to_string(p + 1) + " > " + (root / (who[p] + ".log")).string() + " 2>&1 & ";
  }
  const auto ran = Shell(together + "wait");
  LONGS_EQUAL_TEXT(0, ran.code, ran.output.c_str());

  // Recounted from the records: each finger position of each non-practice detection trial.
  std::map<std::string, Count> by_block;
  std::map<std::string, int> staircase_trials;
  std::map<std::string, std::vector<double>> reversals;  // |comparison − reference| at each
  std::string dirs;
  for (const std::string& p : who) {
    std::ifstream log(root / (p + ".log"));
    std::stringstream text;
    text << log.rdbuf();
    std::ifstream session_in(root / p / "session.json");
    const json session = json::parse(session_in);
    CHECK_TEXT(session["complete"].get<bool>(), text.str().c_str());
    std::ifstream trials(root / p / "trials.jsonl");
    for (std::string line; std::getline(trials, line);) {
      const json t = json::parse(line);
      if (t["kind"] == "staircase") {
        ++staircase_trials[p];
        const json& s = t["staircase"];
        if (s["reversal"].get<bool>())
          reversals[p].push_back(
              std::fabs(s["comparison"].get<double>() - s["reference"].get<double>()));
        continue;
      }
      if (t["practice"].get<bool>()) continue;
      Count& c = by_block[t["block"].get<std::string>()];
      ++c.trials;
      for (size_t i = 0; i < t["expected"].size(); ++i) {
        const bool expected = t["expected"][i].get<bool>();
        const bool marked = t["answer"]["fingers"][i].get<bool>();
        (expected ? (marked ? c.tp : c.fn) : (marked ? c.fp : c.tn))++;
      }
    }
    CHECK_TEXT(staircase_trials[p] > 0, p.c_str());
    dirs += " " + (root / p).string();
  }
  LONGS_EQUAL(2, by_block.size());
  LONGS_EQUAL(3 * 4, by_block["single-finger"].trials);
  LONGS_EQUAL(3 * 4, by_block["three-finger"].trials);

  const fs::path out = root / "report";
  const auto report = Palpa("study report" + dirs + " --out " + out.string());
  LONGS_EQUAL_TEXT(0, report.code, report.output.c_str());
  CHECK(fs::file_size(out / "report.html") > 0);
  std::ifstream html_in(out / "report.html");
  std::stringstream html;
  html << html_in.rdbuf();
  for (const std::string& p : who) CHECK_TEXT(html.str().find(p) != std::string::npos, p.c_str());
  CHECK(html.str().find("sim:thesis-pneumatic-3") != std::string::npos);  // the provenance
  const auto blocks = Csv(out / "blocks.csv");
  LONGS_EQUAL(2, blocks.size());
  for (const auto& row : blocks) {
    const Count& c = by_block[row.at("block")];
    const std::string block = row.at("block");
    LONGS_EQUAL_TEXT(c.trials, std::stoi(row.at("trials")), block.c_str());
    LONGS_EQUAL_TEXT(c.tp, std::stoi(row.at("tp")), block.c_str());
    LONGS_EQUAL_TEXT(c.fp, std::stoi(row.at("fp")), block.c_str());
    LONGS_EQUAL_TEXT(c.tn, std::stoi(row.at("tn")), block.c_str());
    LONGS_EQUAL_TEXT(c.fn, std::stoi(row.at("fn")), block.c_str());
    LONGS_EQUAL_TEXT(3 * c.trials, std::stoi(row.at("positions")), block.c_str());
    // Sensitivity and specificity have values: both blocks showed tumours and no tumour.
    DOUBLES_EQUAL(static_cast<double>(c.tp) / (c.tp + c.fn), std::stod(row.at("se")), 1e-9);
    DOUBLES_EQUAL(static_cast<double>(c.tn) / (c.tn + c.fp), std::stod(row.at("sp")), 1e-9);
    CHECK_TEXT(!row.at("acc").empty() && !row.at("mean_time_ms").empty(), block.c_str());
  }
  LONGS_EQUAL(4, Csv(out / "comparisons.csv").size());  // Se, Sp, PPV, ACC between the modes

  // Each participant's staircase: the JND over the block's last two reversals (reversals_used).
  const auto staircases = Csv(out / "staircases.csv");
  LONGS_EQUAL(who.size(), staircases.size());
  for (const auto& row : staircases) {
    const std::string p = row.at("participant");
    LONGS_EQUAL_TEXT(staircase_trials[p], std::stoi(row.at("trials")), p.c_str());
    STRCMP_EQUAL("jnd", row.at("block").c_str());
    STRCMP_EQUAL("2", row.at("reversals_used").c_str());
    const std::vector<double>& r = reversals[p];
    CHECK_TEXT(r.size() >= 2, p.c_str());  // the staircase got as far as its JND
    LONGS_EQUAL_TEXT(r.size(), std::stoi(row.at("reversals")), p.c_str());
    CHECK_TEXT(!row.at("jnd").empty(), p.c_str());
    DOUBLES_EQUAL((r[r.size() - 1] + r[r.size() - 2]) / 2, std::stod(row.at("jnd")), 1e-9);
  }

  // Provenance: every session's simulated board, its seed and unit, as the runner recorded them.
  const auto sessions = Csv(out / "sessions.csv");
  LONGS_EQUAL(who.size(), sessions.size());
  for (const auto& row : sessions) {
    std::ifstream in(fs::path(row.at("dir")) / "session.json");
    const json provenance = json::parse(in)["provenance"];
    STRCMP_EQUAL("sim:thesis-pneumatic-3", row.at("board").c_str());
    STRCMP_EQUAL(provenance["palpa_version"].get<std::string>().c_str(),
                 row.at("palpa_version").c_str());
    STRCMP_EQUAL(std::to_string(provenance["sim"]["seed"].get<int>()).c_str(),
                 row.at("sim_seed").c_str());
    CHECK(!row.at("firmware_version").empty() && !row.at("config_crc").empty());
  }
  fs::remove_all(root);
}
