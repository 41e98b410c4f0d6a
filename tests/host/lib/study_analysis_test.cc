// A study's analysis on synthetic sessions with counts known by construction (study_fixture.h):
// what is counted (finger positions of non-practice trials), per block, condition and
// participant; the modes compared; staircase JNDs; what is refused; and the report's files.
#include "palpa/host/study_analysis.h"

#include <algorithm>
#include <cmath>

#include "CppUTest/TestHarness.h"
#include "palpa/host/study_report.h"
#include "study_fixture.h"

namespace ph = palpa::host;
namespace pt = palpa::testing;

namespace {

ph::StudyAnalysis Analysed(std::vector<ph::SessionRecords> sessions) {
  auto a = ph::AnalyseStudy(std::move(sessions));
  CHECK_TEXT(a.ok(), a.message.c_str());
  return a.value;
}

void CheckCounts(const ph::DetectionCounts& c, int64_t tp, int64_t fp, int64_t tn, int64_t fn) {
  CHECK_EQUAL(tp, c.tp);
  CHECK_EQUAL(fp, c.fp);
  CHECK_EQUAL(tn, c.tn);
  CHECK_EQUAL(fn, c.fn);
}

const ph::ParticipantMode& Of(const ph::StudyAnalysis& a, const std::string& who,
                              ph::TrialMode mode) {
  for (const ph::ParticipantMode& p : a.participant_modes) {
    if (p.participant == who && p.mode == mode) return p;
  }
  FAIL(("no participant " + who).c_str());
  return a.participant_modes.front();
}

}  // namespace

TEST_GROUP(StudyAnalysis){};

TEST(StudyAnalysis, EachFingerPositionOfEachNonPracticeTrialCountsOnce) {
  const ph::StudyAnalysis a = Analysed(pt::ThesisShapedStudy());
  CHECK_EQUAL(2u, a.blocks.size());
  // 3 positions × 14 stimuli × 12 participants = 504 per mode; 168 times; practice left out.
  const ph::BlockSummary& seq = a.blocks[0];
  CHECK(seq.mode == ph::TrialMode::kSequential);
  CHECK_EQUAL(168, seq.tally.trials);
  CHECK_EQUAL(168u, seq.tally.times_ms.size());
  CheckCounts(seq.tally.counts, 138, 21, 327, 18);
  CheckCounts(a.blocks[1].tally.counts, 146, 11, 337, 10);
  DOUBLES_EQUAL(138.0 / 156, ph::Sensitivity(seq.tally.counts).value(), 1e-15);
  DOUBLES_EQUAL(327.0 / 348, ph::Specificity(seq.tally.counts).value(), 1e-15);
  DOUBLES_EQUAL(138.0 / 159, ph::Precision(seq.tally.counts).value(), 1e-15);
  DOUBLES_EQUAL(465.0 / 504, ph::Accuracy(seq.tally.counts).value(), 1e-15);
  CHECK_EQUAL(28, a.summaries[0].detection_trials);
  CHECK_EQUAL(2, a.summaries[0].practice_trials);
  // 14 conditions per block, each 12 trials and 36 positions.
  CHECK_EQUAL(28u, a.conditions.size());
  for (const ph::ConditionSummary& c : a.conditions) CHECK_EQUAL(36, c.tally.counts.total());
  // Participant 1 has 2 of the sequential FNs (18 over 12: one each, the first six a second) and
  // 2 FPs (21: the first nine a second); participant 12 has 1 and 1, and none simultaneous.
  CheckCounts(Of(a, "P1", ph::TrialMode::kSequential).tally.counts, 11, 2, 27, 2);
  CheckCounts(Of(a, "P12", ph::TrialMode::kSequential).tally.counts, 12, 1, 28, 1);
  CheckCounts(Of(a, "P12", ph::TrialMode::kSimultaneous).tally.counts, 13, 0, 29, 0);
}

TEST(StudyAnalysis, TheModesAreComparedAsTheThesisDid) {
  const ph::StudyAnalysis a = Analysed(pt::ThesisShapedStudy());
  CHECK_TRUE(a.comparison.has_value());
  const ph::ModeComparison& c = *a.comparison;
  CHECK_EQUAL(12, c.participants_paired);
  const ph::MetricComparison& se = c.metrics[0];
  STRCMP_EQUAL("Se", se.metric.c_str());
  DOUBLES_EQUAL(138, se.sequential.k, 0);
  DOUBLES_EQUAL(156, se.sequential.n, 0);
  DOUBLES_EQUAL(146, se.simultaneous.k, 0);
  // The thesis's intervals: the same proportions over every finger position (504).
  const ph::ProportionComparison thesis =
      ph::CompareProportions({138.0 / 156 * 504, 504}, {146.0 / 156 * 504, 504});
  DOUBLES_EQUAL(thesis.combined, se.by_thesis_n.combined, 1e-12);
  CHECK(se.by_thesis_n.combined < se.by_own_n.combined);  // more positions, narrower
  // Se per participant rises by 1/13 for P1–P6 (2 → 1 FN) and P11–P12 (1 → 0), not for P7–P10:
  // 8 equal positive differences, T = 0, exact p = 2/2⁸.
  CHECK_EQUAL(8, se.participants.n);
  DOUBLES_EQUAL(0, se.participants.t, 0);
  DOUBLES_EQUAL(36, se.participants.w, 1e-12);
  DOUBLES_EQUAL(2.0 / 256, se.participants.p, 1e-15);
  CHECK_TRUE(se.participants.significant_by_table);
  // Sp: FP 2 → 1 for P1–P9, 1 → 1 for P10, P11, 1 → 0 for P12: 10 differences, p = 2/2¹⁰.
  CHECK_EQUAL(10, c.metrics[1].participants.n);
  DOUBLES_EQUAL(2.0 / 1024, c.metrics[1].participants.p, 1e-15);
  // Times: simultaneous 2 s less, plus 10 ms × (p mod 3) — 1.99 s less on average.
  CHECK_EQUAL(168, c.trials_sequential);
  DOUBLES_EQUAL(-1990, c.times_welch.mean_difference, 1e-9);
  DOUBLES_EQUAL(-1990, c.times_paired.mean_difference, 1e-9);
  CHECK(c.times_welch.p < 1e-10);
  CHECK(c.times_paired.p < 1e-10);
  CHECK_EQUAL(12, c.times_wilcoxon.n);
}

TEST(StudyAnalysis, OneModeOnlyHasNoComparison) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  for (ph::SessionRecords& s : sessions) {
    s.trials.erase(std::remove_if(s.trials.begin(), s.trials.end(),
                                  [](const ph::TrialRecord& t) {
                                    return t.mode == ph::TrialMode::kSimultaneous;
                                  }),
                   s.trials.end());
  }
  CHECK_FALSE(Analysed(sessions).comparison.has_value());
}

TEST(StudyAnalysis, StaircaseJndIsTheMeanOfTheLastReversals) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  // Reversals at differences 8, 4, 6, 5, 7, 5 kPa; the last four: (6 + 5 + 7 + 5) / 4 = 5.75.
  pt::AddStaircase(sessions[0], {10, 8, 6, 4, 5, 6, 5, 4, 5, 7, 6, 5}, {1, 3, 5, 6, 9, 11});
  pt::AddStaircase(sessions[1], {10, 8, 6}, {1});  // one reversal of four
  const ph::StudyAnalysis a = Analysed(sessions);
  CHECK_EQUAL(2u, a.staircases.size());
  const ph::StaircaseSummary& s = a.staircases[0];
  CHECK_EQUAL(12, s.trials);
  CHECK_EQUAL(6, s.reversals);
  DOUBLES_EQUAL(5.75, s.jnd, 1e-12);
  DOUBLES_EQUAL(30, s.reference, 1e-12);
  DOUBLES_EQUAL(5.75 / 30, s.weber, 1e-12);
  CHECK_TRUE(s.enough);
  CHECK_FALSE(a.staircases[1].enough);
  DOUBLES_EQUAL(8, a.staircases[1].jnd, 1e-12);
  // Without the block's reversals_used there is no JND to give: refused, naming the field.
  for (ph::SessionRecords& r : sessions)
    r.session.study["blocks"][2]["staircase"].erase("reversals_used");
  const auto refused = ph::AnalyseStudy(sessions);
  CHECK_FALSE(refused.ok());
  STRCMP_CONTAINS("P1/session.json: study.blocks[2].staircase.reversals_used",
                  refused.message.c_str());
  // Nor for staircase trials of a block the study does not have.
  for (ph::SessionRecords& r : sessions) r.session.study["blocks"][2]["name"] = "other";
  const auto unknown = ph::AnalyseStudy(sessions);
  CHECK_FALSE(unknown.ok());
  STRCMP_CONTAINS("P1/session.json: study.blocks: no block \"jnd\"", unknown.message.c_str());
}

TEST(StudyAnalysis, SessionsOfAnotherStudyOrAParticipantTwiceAreRefused) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  sessions[3].session.study["name"] = "jamming";
  auto r = ph::AnalyseStudy(sessions);
  CHECK_FALSE(r.ok());
  STRCMP_CONTAINS("P4: study \"jamming\", but P1 is study \"pneumatic\"", r.message.c_str());
  sessions = pt::ThesisShapedStudy();
  sessions[5].session.study["blocks"] = {"three-finger"};
  r = ph::AnalyseStudy(sessions);
  STRCMP_CONTAINS(
      "P6: study \"pneumatic\" was run with another definition than P1's "
      "(study.blocks differs)",
      r.message.c_str());
  sessions = pt::ThesisShapedStudy();
  sessions[2].session.participant = "P1";
  r = ph::AnalyseStudy(sessions);
  STRCMP_CONTAINS("P3: participant \"P1\" is in P1 already", r.message.c_str());
  CHECK_FALSE(ph::AnalyseStudy({}).ok());
  sessions = pt::ThesisShapedStudy();
  sessions[4].trials[7].mode.reset();  // a record a program built, never read from a file
  r = ph::AnalyseStudy(sessions);
  STRCMP_CONTAINS("P5: trial 7: a detection trial needs a mode", r.message.c_str());
}

TEST(StudyAnalysis, AnUnfinishedSessionIsIncludedAndNoted) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  sessions[1].session.complete = false;
  sessions[1].session.finished_utc.reset();
  sessions[1].warnings.push_back("P2/trials.jsonl: line 31: torn");
  const ph::StudyAnalysis a = Analysed(sessions);
  CHECK_EQUAL(2u, a.notes.size());
  STRCMP_CONTAINS("P2: the session of P2 did not complete", a.notes[0].c_str());
  STRCMP_CONTAINS("torn", a.notes[1].c_str());
}

TEST(StudyAnalysis, TheReportHoldsEveryTableAndChartAndNoScript) {
  std::vector<ph::SessionRecords> sessions = pt::ThesisShapedStudy();
  sessions[0].session.participant = "<P&1>";
  pt::AddStaircase(sessions[0], {10, 8, 6, 4, 5}, {1, 3});
  const std::vector<ph::ReportFile> files = ph::RenderStudyReport(Analysed(sessions));
  std::vector<std::string> names;
  for (const ph::ReportFile& f : files) names.push_back(f.name);
  const std::vector<std::string> expected = {
      "report.html",      "sessions.csv",    "blocks.csv", "conditions.csv",
      "participants.csv", "comparisons.csv", "times.csv",  "staircases.csv"};
  CHECK(names == expected);
  const std::string& html = files[0].text;
  size_t charts = 0;
  for (size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1))
    ++charts;
  CHECK_EQUAL(3u, charts);  // the modes' metrics, the participants, the staircases
  CHECK(html.find("<script") == std::string::npos);
  CHECK(html.find("&lt;P&amp;1&gt;") != std::string::npos);  // escaped, never markup
  CHECK(html.find("<P&1>") == std::string::npos);
  STRCMP_CONTAINS("88.5 % [82.5, 92.6] (138/156)", html.c_str());
  // Every CSV row has its header's columns; the blocks' counts as constructed.
  for (const ph::ReportFile& f : files) {
    if (f.name == "report.html" || f.name == "sessions.csv") continue;  // sessions: quoted fields
    size_t at = 0, columns = 0;
    for (size_t end; (end = f.text.find('\n', at)) != std::string::npos; at = end + 1) {
      const std::string line = f.text.substr(at, end - at);
      const size_t n = static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
      if (at == 0) columns = n;
      CHECK_EQUAL_TEXT(columns, n, (f.name + ": " + line).c_str());
    }
  }
  STRCMP_CONTAINS("one-finger,sequential,168,504,138,21,327,18,", files[2].text.c_str());
  STRCMP_CONTAINS("three-finger,simultaneous,168,504,146,11,337,10,", files[2].text.c_str());
}
