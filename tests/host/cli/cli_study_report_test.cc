// palpa study report on session directories written by the records library: the thesis-shaped
// 12-participant study end to end, and every refusal as exit 2 naming what and where.
#include <filesystem>
#include <fstream>

#include "file_text.h"
#include "palpa/host/file_write.h"
#include "study_fixture.h"
// CppUTest's checks after the standard headers (its leak checker redefines new).
#include "CppUTest/TestHarness.h"
#include "cli_run.h"

namespace fs = std::filesystem;
namespace ph = palpa::host;
namespace pt = palpa::testing;

TEST_GROUP(CliStudyReport) {
  fs::path root;
  std::string dirs;  ///< the session directories, as arguments
  void setup() override {
    root = pt::OwnTempPath("study");
    fs::remove_all(root);
    fs::create_directories(root);
  }
  void teardown() override { fs::remove_all(root); }
  /// Each session written as the runner writes it: session.json whole, trials.jsonl a line per
  /// trial (written at once here: a flush per line is the records tests' business).
  void Write(const std::vector<ph::SessionRecords>& sessions) {
    for (const ph::SessionRecords& s : sessions) {
      const fs::path dir = root / s.dir;
      fs::create_directories(dir);
      CHECK(ph::WriteSession(dir, s.session).ok());
      std::string lines;
      for (const ph::TrialRecord& t : s.trials) lines += ph::TrialLine(t) + "\n";
      CHECK(ph::WriteFileWhole(dir / ph::kTrialsFileName, lines).ok());
      dirs += " " + dir.string();
    }
  }
};

TEST(CliStudyReport, ReportsTheThesisShapedStudy) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  pt::AddStaircase(sessions[0], {10, 8, 6, 4, 5, 6, 5, 4}, {1, 3, 5, 7});
  Write(sessions);
  const fs::path out = root / "out";
  const pt::Run r = pt::Palpa("study report" + dirs + " --out " + out.string());
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(pt::Has(r, "study pneumatic: 12 sessions"), r.output.c_str());
  CHECK_TEXT(pt::Has(r, "Se  sequential 88.5 % [82.5, 92.6] (138/156), simultaneous 93.6 %"),
             r.output.c_str());
  for (const char* f : {"report.html", "sessions.csv", "blocks.csv", "conditions.csv",
                        "participants.csv", "comparisons.csv", "times.csv", "staircases.csv"})
    CHECK_TEXT(fs::is_regular_file(out / f), f);
  STRCMP_CONTAINS("one-finger,sequential,168,504,138,21,327,18,",
                  pt::FileText(out / "blocks.csv").c_str());
  STRCMP_CONTAINS("P1,jnd,kPa,8,4,4,true,5.5,30,", pt::FileText(out / "staircases.csv").c_str());
  // Every session's provenance is listed.
  const std::string provenance = pt::FileText(out / "sessions.csv");
  for (int p = 1; p <= 12; ++p)
    STRCMP_CONTAINS((root / ("P" + std::to_string(p))).c_str(), provenance.c_str());
  STRCMP_CONTAINS("1.4.0,c0ffee12,0x5eed,sim,7,12,finger1.json=", provenance.c_str());
  // --json: the same figures for a program.
  const pt::Run j = pt::Palpa("--json study report" + dirs + " --out " + out.string(), "", false);
  LONGS_EQUAL_TEXT(0, j.code, j.output.c_str());
  const auto doc = nlohmann::json::parse(j.output);
  CHECK_EQUAL(12, doc["sessions"].get<int>());
  DOUBLES_EQUAL(138.0 / 156, doc["comparison"][0]["sequential"].get<double>(), 1e-12);
}

TEST(CliStudyReport, RefusalsExitTwoNamingWhatAndWhere) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  sessions.resize(2);
  sessions[1].session.study["name"] = "jamming";
  Write(sessions);
  const std::string p1 = (root / "P1").string(), p2 = (root / "P2").string();
  const std::string out = (root / "out").string();
  pt::ExpectUsage("study report" + dirs + " --out " + out,
                  p2 + ": study \"jamming\", but " + p1 + " is study \"pneumatic\"");
  CHECK_FALSE(fs::exists(out));  // a refused command creates nothing
  pt::ExpectUsage("study report " + p1 + " " + p1, p1 + ": named twice");
  pt::ExpectUsage("study report " + (root / "none").string(),
                  (root / "none/session.json").string());
  pt::ExpectUsage("study report", "needs at least one session directory");
  pt::ExpectUsage("study report " + p1 + " --out", "--out");
  pt::ExpectUsage("study report " + p1 + " --outt x", "unknown option '--outt'");
  pt::ExpectUsage("study", "a subcommand is missing");
  pt::ExpectUsage("study reprot", "did you mean 'report'?");
  // A damaged journal line: file, line and field.
  std::ofstream(root / "P1" / ph::kTrialsFileName, std::ios::app)
      << "{\"index\": 40, \"kind\": \"detection\"}\n";
  pt::ExpectUsage("study report " + p1,
                  (root / "P1/trials.jsonl").string() + ": line 31: block: missing");
  // OUT that is a file, not a directory.
  std::ofstream(root / "file") << "x";
  pt::ExpectUsage("study report " + p2 + " --out " + (root / "file").string(), "not a directory");
}
