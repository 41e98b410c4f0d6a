// Study session records: both files round trip; trials are appended and flushed a line at a time;
// a torn last line is ignored (and cut off by the next append); every other fault is refused
// naming the file, the line and the field.
#include "palpa/host/study_records.h"

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "CppUTest/TestHarness.h"
#include "file_text.h"
#include "fsync_seam.h"

namespace fs = std::filesystem;
namespace ph = palpa::host;
using nlohmann::json;

/// Two JSON values alike (CppUTest prints their text when not).
#define JSON_EQUAL(expected, actual) \
  STRCMP_EQUAL((expected).dump().c_str(), (actual).dump().c_str())

namespace {

void WriteRaw(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

ph::StudySession Session() {
  ph::StudySession s;
  s.study = {{"name", "pneumatic-three"}, {"blocks", json::array({"one", "three"})}};
  s.participant = "P07";
  s.seed = 18446744073709551615u;  // the largest: seeds are unsigned 64-bit
  s.order = {{0, "three-finger", "10-30-10", true},
             {1, "three-finger", "30-30-30", false},
             {2, "staircase", "jnd", false}};
  s.provenance = {"0.9.0",
                  "1.2.3",
                  "c0ffee",
                  "0x1A2b",
                  {{"finger1.json", std::string(64, 'a')}},
                  "sim",
                  ph::SimProvenance{1, 12}};
  s.started_utc = "2026-11-26T18:00:00Z";
  return s;
}

ph::TrialRecord Detection(int64_t index, const std::string& condition, bool practice) {
  ph::TrialRecord t;
  t.index = index;
  t.block = "three-finger";
  t.mode = ph::TrialMode::kSimultaneous;
  t.practice = practice;
  t.condition = condition;
  t.stimulus = {10, 30, 10};
  t.unit = "kPa";
  t.expected = {false, true, false};
  t.answer = {true, {false, true, true}};
  t.settled_board_ms = 123456;
  t.answered_board_ms = 125801;
  t.time_ms = 2345;
  return t;
}

ph::TrialRecord Staircase(int64_t index) {
  ph::TrialRecord t;
  t.index = index;
  t.block = "staircase";
  t.kind = ph::TrialKind::kStaircase;
  t.staircase = {30, 34.5, "kPa", true, false};
  t.settled_board_ms = 10;
  t.answered_board_ms = 1010;
  t.time_ms = 1000;
  return t;
}

/// The refusal's message, which must contain every one of `parts`.
void CheckRefused(const ph::Outcome& r, std::initializer_list<const char*> parts) {
  CHECK_FALSE(r.ok());
  CHECK_EQUAL(static_cast<int>(ph::Status::kInvalidArgument), static_cast<int>(r.status));
  for (const char* part : parts) {
    if (r.message.find(part) == std::string::npos)
      FAIL(("'" + r.message + "' lacks '" + part + "'").c_str());
  }
}

}  // namespace

TEST_GROUP(StudyRecords) {
  fs::path dir;
  void setup() override {
    dir = MakeTestDir("palpa-study");
    CHECK(!dir.empty());
  }
  void teardown() override { RemoveTestDir(dir); }
  fs::path Trials() const { return dir / ph::kTrialsFileName; }
  /// Writes the session and the trials, then `line` as the trials file's line 3 (after two good
  /// ones), and reads the directory back.
  ph::Result<ph::SessionRecords> WithThirdLine(const std::string& line) {
    CHECK(ph::WriteSession(dir, Session()).ok());
    WriteRaw(Trials(), ph::TrialLine(Detection(0, "10-30-10", true)) + "\n" +
                           ph::TrialLine(Detection(1, "30-30-30", false)) + "\n" + line + "\n");
    return ph::ReadSessionDir(dir);
  }
  /// The third line as Staircase(2) with `edit` applied to its JSON.
  ph::Result<ph::SessionRecords> WithTrialEdit(const std::function<void(json&)>& edit,
                                               bool staircase = false) {
    json j = ph::TrialToJson(staircase ? Staircase(2) : Detection(1, "30-30-30", false));
    edit(j);
    CHECK(ph::WriteSession(dir, Session()).ok());
    WriteRaw(Trials(), ph::TrialLine(Detection(0, "10-30-10", true)) + "\n" + j.dump() + "\n");
    return ph::ReadSessionDir(dir);
  }
  ph::Result<ph::SessionRecords> WithSessionEdit(const std::function<void(json&)>& edit) {
    json j = ph::SessionToJson(Session());
    edit(j);
    WriteRaw(dir / ph::kSessionFileName, j.dump());
    return ph::ReadSessionDir(dir);
  }
};

TEST(StudyRecords, SessionAndTrialsRoundTripThroughTheirFiles) {
  ph::StudySession s = Session();
  s.extra = {{"added_later", {1, 2}}};
  s.provenance.extra = {{"host", "lab-pc"}};
  CHECK(ph::WriteSession(dir, s).ok());
  const std::vector<ph::TrialRecord> trials = {Detection(0, "10-30-10", true),
                                               Detection(1, "30-30-30", false), Staircase(2)};
  for (const ph::TrialRecord& t : trials) CHECK(ph::AppendTrial(dir, t).ok());
  s.finished_utc = "2026-11-26T18:30:00.125Z";
  s.complete = true;
  CHECK(ph::WriteSession(dir, s).ok());

  const auto r = ph::ReadSessionDir(dir);
  CHECK_TRUE(r.ok());
  CHECK(r.value.warnings.empty());
  JSON_EQUAL(ph::SessionToJson(s), ph::SessionToJson(r.value.session));
  CHECK_EQUAL("pneumatic-three", r.value.session.StudyName());
  CHECK_EQUAL(18446744073709551615u, r.value.session.seed);
  JSON_EQUAL(json({1, 2}), r.value.session.extra["added_later"]);
  CHECK_EQUAL(trials.size(), r.value.trials.size());
  for (size_t i = 0; i < trials.size(); ++i)
    JSON_EQUAL(ph::TrialToJson(trials[i]), ph::TrialToJson(r.value.trials[i]));
  // The journal is one line per trial, each ended by its newline.
  const std::string text = palpa::testing::FileText(Trials());
  CHECK_EQUAL(trials.size(), static_cast<size_t>(std::count(text.begin(), text.end(), '\n')));
  CHECK_EQUAL('\n', text.back());
  // A real board: no simulator provenance, written as null.
  s.provenance.sim.reset();
  const auto back = ph::SessionFromJson(ph::SessionToJson(s));
  CHECK_TRUE(back.ok());
  CHECK_FALSE(back.value.provenance.sim.has_value());
  CHECK(ph::SessionToJson(s)["provenance"]["sim"].is_null());
}

TEST(StudyRecords, EachTrialIsFlushedToDiskAndANewJournalsDirectoryToo) {
  CHECK(ph::WriteSession(dir, Session()).ok());
  g_record_fsyncs = true;
  CHECK(ph::AppendTrial(dir, Detection(0, "10-30-10", true)).ok());
  CHECK_EQUAL(2u, g_fsync_count);  // the new file, then the directory that names it
  CHECK_EQUAL('f', g_fsynced[0]);
  CHECK_EQUAL('d', g_fsynced[1]);
  g_fsync_count = 0;
  CHECK(ph::AppendTrial(dir, Detection(1, "30-30-30", false)).ok());
  CHECK_EQUAL(1u, g_fsync_count);
  CHECK_EQUAL('f', g_fsynced[0]);
}

TEST(StudyRecords, ATornLastLineIsIgnoredWithAWarningAndCutOffByTheNextAppend) {
  CHECK(ph::WriteSession(dir, Session()).ok());
  CHECK(ph::AppendTrial(dir, Detection(0, "10-30-10", true)).ok());
  const std::string whole = ph::TrialLine(Detection(1, "30-30-30", false));
  std::ofstream(Trials(), std::ios::app) << whole.substr(0, whole.size() / 2);
  auto r = ph::ReadSessionDir(dir);
  CHECK_TRUE(r.ok());
  CHECK_EQUAL(1u, r.value.trials.size());
  CHECK_EQUAL(1u, r.value.warnings.size());
  STRCMP_CONTAINS((Trials().string() + ": line 2: torn").c_str(), r.value.warnings[0].c_str());
  // Even a line that parses is torn without its newline: the write never finished.
  WriteRaw(Trials(), ph::TrialLine(Detection(0, "10-30-10", true)));
  r = ph::ReadSessionDir(dir);
  CHECK_EQUAL(0u, r.value.trials.size());
  CHECK_EQUAL(1u, r.value.warnings.size());

  // The next append (a resumed session) drops the torn line and says so.
  std::ofstream(Trials(), std::ios::trunc) << ph::TrialLine(Detection(0, "10-30-10", true)) << "\n"
                                           << whole.substr(0, 20);
  const ph::Outcome appended = ph::AppendTrial(dir, Detection(1, "30-30-30", false));
  CHECK_TRUE(appended.ok());
  CHECK_EQUAL(1u, appended.notes.size());
  STRCMP_CONTAINS("torn", appended.notes[0].c_str());
  r = ph::ReadSessionDir(dir);
  CHECK_TRUE(r.ok());
  CHECK_EQUAL(2u, r.value.trials.size());
  CHECK(r.value.warnings.empty());
}

TEST(StudyRecords, NoTrialsYetIsASessionWithNone) {
  CHECK(ph::WriteSession(dir, Session()).ok());
  const auto r = ph::ReadSessionDir(dir);
  CHECK_TRUE(r.ok());
  CHECK(r.value.trials.empty());
}

TEST(StudyRecords, MissingSessionFileAndLinkedJournalAreRefusedByName) {
  const auto missing = ph::ReadSessionDir(dir);
  CHECK_EQUAL(static_cast<int>(ph::Status::kNotFound), static_cast<int>(missing.status));
  STRCMP_CONTAINS((dir / "session.json").c_str(), missing.message.c_str());
  CHECK(ph::WriteSession(dir, Session()).ok());
  WriteRaw(dir / "elsewhere", "");
  fs::create_symlink(dir / "elsewhere", Trials());
  const ph::Outcome linked = ph::AppendTrial(dir, Detection(0, "10-30-10", true));
  CHECK_FALSE(linked.ok());
  STRCMP_CONTAINS("symbolic link", linked.message.c_str());
  CHECK_EQUAL("", palpa::testing::FileText(dir / "elsewhere"));
}

TEST(StudyRecords, MalformedTrialLinesAreRefusedNamingFileLineAndField) {
  const std::string at = Trials().string() + ": line 3: ";
  CheckRefused(WithThirdLine(""), {(at + "empty line").c_str()});
  CheckRefused(WithThirdLine("{\"index\": 2,"), {at.c_str(), "not valid JSON"});
  CheckRefused(WithThirdLine("[1]"), {at.c_str(), "must be an object"});
  // Against the plan: unknown index, another block, practice, condition; a repeated trial.
  CheckRefused(WithThirdLine(ph::TrialLine(Detection(9, "30-30-30", false))),
               {at.c_str(), "index: 9 is not in session.json's order"});
  ph::TrialRecord t = Detection(1, "30-30-30", false);
  t.block = "one-finger";
  CheckRefused(WithThirdLine(ph::TrialLine(t)), {at.c_str(), "block: \"one-finger\""});
  CheckRefused(WithThirdLine(ph::TrialLine(Detection(1, "30-30-30", true))),
               {at.c_str(), "practice: true"});
  CheckRefused(WithThirdLine(ph::TrialLine(Detection(1, "10-10-10", false))),
               {at.c_str(), "condition: \"10-10-10\""});
  CheckRefused(WithThirdLine(ph::TrialLine(Detection(1, "30-30-30", false))),
               {at.c_str(), "trial 1 is recorded on line 2 already"});
}

TEST(StudyRecords, EveryTrialFieldIsChecked) {
  const std::string at = Trials().string() + ": line 2: ";
  struct Case {
    std::function<void(json&)> edit;
    const char* says;
    bool staircase = false;
  };
  const Case cases[] = {
      {[](json& j) { j.erase("index"); }, "index: missing"},
      {[](json& j) { j["index"] = -1; }, "index: -1 is outside"},
      {[](json& j) { j["kind"] = "guess"; }, "kind: \"guess\" is not one of"},
      {[](json& j) { j["mode"] = "both"; }, "mode: \"both\" is not one of"},
      {[](json& j) { j.erase("mode"); }, "mode: missing"},
      {[](json& j) { j["practice"] = 0; }, "practice: must be true or false"},
      {[](json& j) { j["stimulus"] = json::array(); }, "stimulus: has 0 entries"},
      {[](json& j) { j["stimulus"][1] = "high"; }, "stimulus[1]: must be a number"},
      {[](json& j) { j["unit"] = ""; }, "unit: must be a non-empty string"},
      {[](json& j) {
         j["expected"] = {true, false};
       },
       "expected: has 2 entries, needs 3"},
      {[](json& j) { j["expected"][2] = 1; }, "expected[2]: must be true or false"},
      {[](json& j) { j["answer"]["fingers"][0] = nullptr; }, "answer.fingers[0]: must be true"},
      {[](json& j) { j["answer"]["tumour"] = false; }, "answer.fingers[1]: marked, but"},
      {[](json& j) { j["answer"]["sure"] = true; }, "answer.sure: unknown field"},
      {[](json& j) { j["staircase"] = json::object(); }, "staircase: only a staircase trial"},
      {[](json& j) { j["time_ms"] = 2000; }, "time_ms: 2000 is not answered_board_ms"},
      {[](json& j) { j["settled_board_ms"] = 1.5; }, "settled_board_ms: must be an integer"},
      {[](json& j) { j["unit"] = "kPa"; }, "unit: a staircase trial has none", true},
      {[](json& j) { j.erase("staircase"); }, "staircase: missing", true},
      {[](json& j) { j["staircase"]["correct"] = "yes"; }, "staircase.correct: must be true", true},
      {[](json& j) { j["staircase"]["reference"] = "x"; }, "staircase.reference: must be a number",
       true},
      {[](json& j) { j["block"] = "other"; }, "block: \"other\", but the order plans", true},
  };
  for (const Case& c : cases)
    CheckRefused(WithTrialEdit(c.edit, c.staircase), {at.c_str(), c.says});
  // A staircase trial outside the plan (the staircase decides how many it takes) is fine, and a
  // field the format gained later is kept.
  CHECK_TRUE(WithTrialEdit([](json& j) { j["index"] = 77; }, true).ok());
  const auto later = WithTrialEdit([](json& j) { j["trigger_us"] = 5; });
  CHECK_TRUE(later.ok());
  JSON_EQUAL(json(5), later.value.trials[1].extra["trigger_us"]);
}

TEST(StudyRecords, EverySessionFieldIsChecked) {
  const std::string at = (dir / "session.json").string() + ": ";
  struct Case {
    std::function<void(json&)> edit;
    const char* says;
  };
  const Case cases[] = {
      {[](json& j) { j["format"] = "palpa-study-session/2"; }, "format: \"palpa-study-session/2\""},
      {[](json& j) { j.erase("format"); }, "format: missing"},
      {[](json& j) { j["study"] = 3; }, "study: must be an object"},
      {[](json& j) { j["study"].erase("name"); }, "study.name: must be a non-empty string"},
      {[](json& j) { j["participant"] = ""; }, "participant: must be a non-empty string"},
      {[](json& j) { j["seed"] = -4; }, "seed: must be an integer, 0 or more"},
      {[](json& j) { j["order"][1]["index"] = 0; }, "order[1].index: 0 is planned twice"},
      {[](json& j) { j["order"][2].erase("practice"); }, "order[2].practice: missing"},
      {[](json& j) { j["order"][0]["extra"] = 1; }, "order[0].extra: unknown field"},
      {[](json& j) { j["provenance"]["config_crc"] = "1234"; }, "provenance.config_crc: \"1234\""},
      {[](json& j) { j["provenance"]["calibration_files"]["f.json"] = "abc"; },
       "provenance.calibration_files.f.json: must be a SHA-256"},
      {[](json& j) { j["provenance"].erase("sim"); }, "provenance.sim: missing"},
      {[](json& j) { j["provenance"]["sim"]["seed"] = "1"; }, "provenance.sim.seed: must be"},
      {[](json& j) { j["provenance"]["sim"]["speed"] = 1; }, "provenance.sim.speed: unknown"},
      {[](json& j) { j["provenance"]["board"] = nullptr; }, "provenance.board: missing"},
      {[](json& j) { j["started_utc"] = "26/11/2026 18:00"; }, "started_utc: \"26/11/2026"},
      {[](json& j) { j["started_utc"] = "2026-11-26T18:00:00.Z"; }, "started_utc: \"2026"},
      {[](json& j) { j.erase("finished_utc"); }, "finished_utc: missing (null while"},
      {[](json& j) { j["complete"] = true; }, "complete: true, but finished_utc is null"},
  };
  for (const Case& c : cases) CheckRefused(WithSessionEdit(c.edit), {at.c_str(), c.says});
  WriteRaw(dir / ph::kSessionFileName, "{\"format\": ");
  CheckRefused(ph::ReadSessionDir(dir), {at.c_str(), "not valid JSON"});
}

TEST(StudyRecords, ASimulatedBoardsSeedAndUnitAreReadFromWhatPalpaSimSaid) {
  const auto said = ph::SimProvenanceOf(
      "palpa-sim: thesis-pneumatic-3, plant level 3, unit 12, seed 7, speed 1x");
  CHECK(said.has_value());
  LONGS_EQUAL(12, said->unit);
  CHECK(said->seed == 7);
  // The link's description carries the announcement after the address.
  const auto link = ph::SimProvenanceOf(
      "sim:thesis-5finger (palpa-sim on tcp:127.0.0.1:4001: thesis-5finger, plant level 3, "
      "unit 0, seed 1, speed 1x)");
  CHECK(link.has_value());
  LONGS_EQUAL(0, link->unit);
  CHECK(link->seed == 1);
  CHECK_FALSE(ph::SimProvenanceOf("tcp:127.0.0.1:4001").has_value());
  CHECK_FALSE(ph::SimProvenanceOf("palpa-sim: x, unit 3").has_value());  // no seed
  CHECK_FALSE(ph::SimProvenanceOf("subunit 3, seed 1").has_value());     // a word, not the unit
  CHECK_FALSE(ph::SimProvenanceOf("unit twelve, seed 1").has_value());
}
