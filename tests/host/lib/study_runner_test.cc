// The study runner: the settle rule on its own, answers typed and checked, and a shortened study
// on palpa-sim answered by the simulated participant — its records, the settle moment against
// the simulator's truth channel, and the refusals (a reused participant, a board that does not
// fit).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "palpa/host/sim_truth.h"
#include "palpa/host/study_participant.h"
#include "palpa/host/study_runner.h"
#include "palpa/host/transport.h"
#include "study_session.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
namespace fs = std::filesystem;

namespace {

const char kShort[] = PALPA_TEST_DATA_DIR "/study_short.json";

/// The short study with one repetition (six trials) and a break after two.
ph::Study Short() {
  auto s = ph::LoadStudy(kShort);
  CHECK_TEXT(s.ok(), s.message.c_str());
  s.value.blocks[0].repetitions = 1;
  s.value.blocks[0].break_every = 2;
  return s.value;
}

std::string TempDir(const std::string& name) {
  const std::string dir = "/tmp/palpa-study-" + std::to_string(getpid()) + "-" + name;
  fs::remove_all(dir);
  return dir;
}

std::vector<nlohmann::json> Trials(const std::string& dir) {
  std::ifstream in(dir + "/trials.jsonl");
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

/// palpa-sim at ten times real time, its truth every 5 ms, every line given a 30 ms chamber model
/// (as a calibration would: the plant's pneumatic line is about that, docs/plant.md).
struct SimBoard {
  std::unique_ptr<ph::Device> device;
  ph::TruthReader truth;
  explicit SimBoard(const char* config = "thesis-pneumatic-3") {
    setenv("PALPA_SIM", PALPA_SIM_PATH, 1);
    std::string address;
    auto t = ph::LaunchSim(config, {"--speed", "10", "--truth-every-ms", "5"}, &address);
    CHECK_TEXT(t.ok(), t.message.c_str());
    ph::DeviceOptions options;
    options.use_calibrations = false;
    auto d = ph::Device::Attach(std::move(t.value), options);
    CHECK_TEXT(d.ok(), d.message.c_str());
    device = std::move(d.value);
    CHECK(truth.Connect(address));
    for (uint8_t l = 0; l < device->info().line_count; ++l) {
      auto line = device->ReadLine(l);
      CHECK_TEXT(line.ok(), line.message.c_str());
      line.value.chamber_tau_us = 30000;
      const ph::Outcome o = device->ConfigureLine(line.value);
      CHECK_TEXT(o.ok(), o.message.c_str());
    }
  }
};

/// Each finger's true output at board time t (the newest sample at or before it).
std::vector<double> TruthAt(const std::vector<ph::TruthReader::Sample>& all, double t) {
  std::vector<double> out;
  for (const auto& s : all) {
    if (s.t_s > t) break;
    out = s.outputs;
  }
  return out;
}

/// A session of `participant` in a fresh directory of its own, on the nominal curves.
ph::StudyRunOptions Session(const std::string& participant) {
  ph::StudyRunOptions o;
  o.out_dir = TempDir(participant);
  o.participant = participant;
  o.use_calibrations = false;
  return o;
}

}  // namespace

TEST_GROUP(StudySettle){};

TEST(StudySettle, TheChamberFollowsTheOutletThroughTheTubesLaw) {
  // An outlet that steps at once, 80 kPa: alone it settles at the step. Behind it a chamber whose
  // lag at the board's reference (−12.5 kPa vacuum, +30 kPa pressure) is 50 ms, through
  // dC/dt = k (O − C)(O + C + 2 p_atm); in absolute u = C + p_atm, w = O + p_atm that is
  // du/dt = k (w² − u²), so u/w's artanh (below w) or arcoth (above) grows at k w: the chamber is
  // within 0.5 kPa after 0.19 s of pressure but 0.84 s of vacuum, the same size. One lag of
  // 50 ms would call both settled at ln(160) × 50 ms = 0.25 s.
  constexpr double kAtm = 101325, kTau = 0.05, kTolerance = 500;
  const auto settled = [](pp::LineKind kind, double tau, double target) {
    ph::SettleRule rule({{0, tau, kind}}, kTolerance, 3000, 0.02);
    rule.Add(0, {0}, {0});
    rule.Restart();
    for (double t = 0.001; t < 2 && !rule.settled_s(); t += 0.001) rule.Add(t, {target}, {target});
    CHECK(rule.settled_s().has_value());
    return *rule.settled_s();
  };
  const auto law = [&](double reference, double target) {
    const double k = 1 / (kTau * 2 * (reference + kAtm)), w = target + kAtm;
    const auto f = [w](double u) { return 0.5 * std::log(std::fabs((w + u) / (w - u))); };
    const double end = w + (kAtm > w ? kTolerance : -kTolerance);
    return (f(end) - f(kAtm)) / (k * w);
  };
  DOUBLES_EQUAL(0.001, settled(pp::LineKind::kPressure, 0, 80000), 1e-9);
  const double pressure = settled(pp::LineKind::kPressure, kTau, 80000);
  const double vacuum = settled(pp::LineKind::kVacuum, kTau, -80000);
  DOUBLES_EQUAL(law(30000, 80000), pressure, 0.003);
  DOUBLES_EQUAL(law(-12500, -80000), vacuum, 0.005);
  CHECK(vacuum > 3 * pressure);
}

TEST(StudySettle, SteadyNearTheSetpointForTheHold) {
  ph::SettleRule rule({{0, 0}}, 500, 3000, 0.05);
  // A regulator 1 kPa off its setpoint, steady: settled (its accuracy is not the clock's).
  rule.Add(0, {11000}, {10000});
  rule.Add(0.03, {11000}, {10000});
  rule.Add(0.04, {11600}, {10000});  // out of the tolerance of itself: the hold starts again
  rule.Add(0.06, {11600}, {10000});
  CHECK_FALSE(rule.settled_s().has_value());
  rule.Add(0.09, {11400}, {10000});
  rule.Add(0.10, {11500}, {10000});
  DOUBLES_EQUAL(0.04, *rule.settled_s(), 1e-9);
  // Steady but beyond the band: a step still on its way (or a stalled line) never settles.
  ph::SettleRule far({{0, 0}}, 500, 3000, 0.05);
  for (double t = 0; t < 1; t += 0.01) far.Add(t, {6000}, {10000});
  CHECK_FALSE(far.settled_s().has_value());
  // A slow ramp (0.2 kPa per 10 ms) inside the band: never within the tolerance for 50 ms.
  ph::SettleRule ramp({{0, 0}}, 500, 3000, 0.05);
  for (int i = 0; i < 20; ++i) ramp.Add(0.01 * i, {8000 + 200.0 * i}, {10000});
  CHECK_FALSE(ramp.settled_s().has_value());
}

TEST_GROUP(StudyAnswers){};

TEST(StudyAnswers, TypedAsPeopleCountAndChecked) {
  ph::TrialPrompt t;
  t.fingers = 3;
  auto a = ph::ParseAnswerText(t, "n");
  CHECK(a.ok() && !a.value.tumour);
  a = ph::ParseAnswerText(t, "1, 2");
  CHECK(a.ok() && a.value.tumour && a.value.fingers == (std::vector<bool>{true, true, false}));
  CHECK(ph::ParseAnswerText(t, "4").message.find("\"4\": type n for no tumour") == 0);
  CHECK(ph::ParseAnswerText(t, "0").message.find("\"0\"") == 0);
  CHECK(ph::ParseAnswerText(t, "2 2").message == "finger 2 twice");
  CHECK(ph::ParseAnswerText(t, "1 2 3").message.find("no tumour (all equal)") != std::string::npos);
  CHECK(ph::ParseAnswerText(t, "").message.find("no answer") == 0);
  CHECK_FALSE(ph::CheckAnswer(t, {false, {true, false, false}}).ok());
  CHECK_FALSE(ph::CheckAnswer(t, {true, {false, false, false}}).ok());
  CHECK_FALSE(ph::CheckAnswer(t, {false, {false, false}}).ok());
  t.kind = ph::BlockKind::kStaircase;
  t.compared = {0, 2};
  CHECK(ph::ParseAnswerText(t, "3").ok());
  CHECK(ph::ParseAnswerText(t, "2").message.find("1 or 3") != std::string::npos);
  CHECK_FALSE(ph::ParseAnswerText(t, "n").ok());
}

TEST_GROUP(StudyRun){};

TEST(StudyRun, AShortStudyOnTheSimulatedBoardAnsweredByTheSimulatedParticipant) {
  SimBoard board;
  const ph::Study study = Short();
  ph::SimulatedParticipantOptions po;
  po.seed = 5;
  ph::SimulatedParticipant participant(board.truth, po);
  ph::StudyRunOptions o = Session("P01");
  o.board = "sim:thesis-pneumatic-3";
  o.sim = ph::SimProvenance{1, 1};
  std::vector<ph::TriggerEvent> triggers;
  o.on_trigger = [&](const ph::TriggerEvent& e) { triggers.push_back(e); };
  const ph::Outcome done = ph::RunStudy(*board.device, study, participant, o);
  CHECK_TEXT(done.ok(), done.message.c_str());

  std::ifstream in(o.out_dir + "/session.json");
  const nlohmann::json session = nlohmann::json::parse(in);
  CHECK(session["complete"].get<bool>());
  STRCMP_EQUAL("P01", session["participant"].get<std::string>().c_str());
  LONGS_EQUAL(ph::StudySeed(study, "P01"), session["seed"].get<uint64_t>());
  const nlohmann::json& p = session["provenance"];
  for (const char* key : {"palpa_version", "firmware_version", "catalog_hash", "config_crc",
                          "calibration_files", "board", "sim", "settle"})
    CHECK_TEXT(p.contains(key), key);
  STRCMP_EQUAL("0.03 s tube lag behind the outlet",
               p["settle"]["line 1"].get<std::string>().c_str());

  const std::vector<nlohmann::json> trials = Trials(o.out_dir);
  LONGS_EQUAL(6, trials.size());
  LONGS_EQUAL(2 * 6, triggers.size());
  LONGS_EQUAL(2, participant.breaks());  // after two scored trials, and between the blocks
  const auto truth = board.truth.All();
  int right = 0;
  for (size_t i = 0; i < trials.size(); ++i) {
    const nlohmann::json& t = trials[i];
    LONGS_EQUAL(i, t["index"].get<int>());
    const nlohmann::json& planned = session["order"][i];
    STRCMP_EQUAL(planned["condition"].get<std::string>().c_str(),
                 t["condition"].get<std::string>().c_str());
    LONGS_EQUAL(t["answered_board_ms"].get<long>() - t["settled_board_ms"].get<long>(),
                t["time_ms"].get<long>());
    CHECK(t["time_ms"].get<long>() > 0);
    DOUBLES_EQUAL(t["settled_board_ms"].get<double>(), triggers[2 * i].board_ms, 1);
    const bool sequential = t["mode"] == "sequential";
    STRCMP_EQUAL(i < 3 ? "simultaneous" : "sequential", t["mode"].get<std::string>().c_str());
    right += t["answer"]["fingers"] == t["expected"];
    if (sequential) continue;
    // The settle moment against the truth: every finger's true output within 0.05 mm (about
    // 1 kPa on Table 5-4's line) of where it ends up, and not long after the truth got there.
    const double settled = t["settled_board_ms"].get<double>() / 1000;
    const std::vector<double> final_out =
        TruthAt(truth, t["answered_board_ms"].get<double>() / 1000);
    const std::vector<double> at = TruthAt(truth, settled);
    for (size_t f = 0; f < 3; ++f) DOUBLES_EQUAL(final_out[f], at[f], 0.05);
    double reached = settled;
    for (double s = settled; s > settled - 1; s -= 0.005) {
      const std::vector<double> then = TruthAt(truth, s);
      bool within = true;
      for (size_t f = 0; f < 3; ++f) within = within && std::fabs(then[f] - final_out[f]) <= 0.05;
      if (!within) break;
      reached = s;
    }
    CHECK_TEXT(settled - reached < 0.15,
               ("settled " + std::to_string(settled - reached) + " s after the truth").c_str());
  }
  CHECK(right >= 4);  // 0/10/30 kPa are far apart for a 15 % Weber fraction

  // The same participant and directory again: refused, nothing written.
  const auto before = fs::file_size(o.out_dir + "/trials.jsonl");
  const ph::Outcome again = ph::RunStudy(*board.device, study, participant, o);
  CHECK_FALSE(again.ok());
  CHECK_TEXT(again.message.find("already holds a complete session of participant P01") !=
                 std::string::npos,
             again.message.c_str());
  o.resume = true;
  CHECK(ph::RunStudy(*board.device, study, participant, o).message.find("complete") !=
        std::string::npos);
  LONGS_EQUAL(before, fs::file_size(o.out_dir + "/trials.jsonl"));
  fs::remove_all(o.out_dir);
}

TEST(StudyRun, AStoppedSessionResumesInTheSameOrder) {
  SimBoard board;
  const ph::Study study = Short();
  ph::SimulatedParticipantOptions po;
  po.stop_at = 2;
  ph::SimulatedParticipant stopping(board.truth, po);
  ph::StudyRunOptions o = Session("P02");
  const ph::Outcome stopped = ph::RunStudy(*board.device, study, stopping, o);
  CHECK_FALSE(stopped.ok());
  CHECK_TEXT(stopped.message.find("2 trials kept; --resume continues") != std::string::npos,
             stopped.message.c_str());
  LONGS_EQUAL(2, Trials(o.out_dir).size());
  // A torn line, as a kill while writing leaves: ignored with a warning and cut.
  { std::ofstream(o.out_dir + "/trials.jsonl", std::ios::app) << "{\"index\": 2, \"blo"; }
  ph::SimulatedParticipant resumed(board.truth, {});
  std::vector<std::string> said;
  o.progress = [&](const std::string& s) { said.push_back(s); };
  o.resume = true;
  o.participant = "P03";
  CHECK(ph::RunStudy(*board.device, study, resumed, o).message.find("P02's session, not P03's") !=
        std::string::npos);
  o.participant = "P02";
  const ph::Outcome done = ph::RunStudy(*board.device, study, resumed, o);
  CHECK_TEXT(done.ok(), done.message.c_str());
  CHECK_TEXT(said.size() >= 2 && said[0].find("line 3: torn") != std::string::npos &&
                 said[1].find("cut off a torn last line") != std::string::npos,
             said.front().c_str());
  const auto trials = Trials(o.out_dir);
  LONGS_EQUAL(6, trials.size());
  std::ifstream in(o.out_dir + "/session.json");
  const nlohmann::json session = nlohmann::json::parse(in);
  for (size_t i = 0; i < trials.size(); ++i) {
    LONGS_EQUAL(i, trials[i]["index"].get<int>());
    CHECK(session["order"][i]["condition"] == trials[i]["condition"]);
  }
  LONGS_EQUAL(1, session["resumed"].size());
  fs::remove_all(o.out_dir);
}

TEST(StudyRun, ABoardThatDoesNotFitIsRefusedBeforeAnythingIsSet) {
  SimBoard board;
  ph::SimulatedParticipant participant(board.truth, {});
  ph::StudyRunOptions o = Session("P04");
  auto jamming = ph::LoadStudy("thesis-jamming");
  const ph::Outcome kind = ph::RunStudy(*board.device, jamming.value, participant, o);
  CHECK_TEXT(
      kind.message.find("finger 0 of this thesis-pneumatic-3 board is not a jamming finger") == 0,
      kind.message.c_str());
  // 2 mm needs more than 40 kPa through the nominal curve (Table 5-4: about 48 kPa).
  ph::Study mm = Short();
  mm.unit = "mm";
  mm.conditions = {{"deep", {0, 2, 0}, {1}}};
  const ph::Outcome cap = ph::RunStudy(*board.device, mm, participant, o);
  CHECK_TEXT(cap.message.find("beyond the study's cap of 40 kPa") != std::string::npos,
             cap.message.c_str());
  o.participant = "../P04";
  CHECK(ph::RunStudy(*board.device, Short(), participant, o).message.find("participant") == 0);
  CHECK_FALSE(fs::exists(o.out_dir));
}

TEST_GROUP(StudyStaircase){};

TEST(StudyStaircase, TwoDownOneUpWithItsReversals) {
  ph::Staircase s;
  s.reference = 10;
  s.start = 20;
  s.step = 2;
  s.reversals = 3;
  ph::StaircaseState st;
  st.difference = 10;
  // Two right: harder (8); one wrong: easier (10), a reversal; two right: harder (8), another;
  // one right, one wrong: easier (10), the third.
  const bool answers[] = {true, true, false, true, true, true, false};
  const double after[] = {10, 8, 10, 10, 8, 8, 10};
  const bool reversal[] = {false, false, true, false, true, false, true};
  for (size_t i = 0; i < 7; ++i) {
    CHECK_FALSE(st.done(s));
    CHECK_EQUAL(reversal[i], st.Answer(s, answers[i]));
    DOUBLES_EQUAL(after[i], st.difference, 1e-12);
  }
  CHECK(st.done(s));
  // Never below a step, never easier than the start.
  for (int i = 0; i < 20; ++i) st.Answer(s, true);
  DOUBLES_EQUAL(2, st.difference, 1e-12);
  for (int i = 0; i < 20; ++i) st.Answer(s, false);
  DOUBLES_EQUAL(10, st.difference, 1e-12);
}

TEST(StudyStaircase, AStaircaseBlockOnTheSimulatedBoard) {
  SimBoard board;
  auto study = ph::ParseStudy(R"({
    "schema": "palpa-study", "schema_version": 1, "name": "jnd", "finger_kind": "pneumatic",
    "fingers": 3, "unit": "kPa", "cap_kpa": 40, "reset": {"hold_ms": 100},
    "blocks": [{"name": "jnd", "kind": "staircase", "mode": "simultaneous",
                "staircase": {"reference": 10, "start": 30, "step": 4, "reversals": 3,
                              "reversals_used": 2, "max_trials": 14, "fingers": [1, 3]}}]})");
  CHECK_TEXT(study.ok(), study.message.c_str());
  ph::SimulatedParticipant participant(board.truth, {});
  ph::StudyRunOptions o = Session("S01");
  const ph::Outcome done = ph::RunStudy(*board.device, study.value, participant, o);
  CHECK_TEXT(done.ok(), done.message.c_str());
  // The comparisons replayed from the records' answers by the rule: the runner followed it.
  ph::StaircaseState replay;
  replay.difference = 20;
  const std::vector<nlohmann::json> trials = Trials(o.out_dir);
  CHECK(!trials.empty() && trials.size() <= 14);
  for (const nlohmann::json& t : trials) {
    STRCMP_EQUAL("staircase", t["kind"].get<std::string>().c_str());
    const nlohmann::json& s = t["staircase"];
    DOUBLES_EQUAL(10 + replay.difference, s["comparison"].get<double>(), 1e-9);
    const nlohmann::json& values = t["values"];
    DOUBLES_EQUAL(0, values[1].get<double>(), 0);  // the middle finger at the reset state
    const nlohmann::json& marked = t["marked"];
    const size_t named = marked[0].get<bool>() ? 0 : 2;
    CHECK(marked[named].get<bool>() && !marked[1].get<bool>());
    CHECK_EQUAL(values[named].get<double>() == s["comparison"].get<double>(),
                s["correct"].get<bool>());
    CHECK_EQUAL(replay.Answer(study.value.blocks[0].staircase, s["correct"].get<bool>()),
                s["reversal"].get<bool>());
  }
  CHECK(replay.done(study.value.blocks[0].staircase));
  fs::remove_all(o.out_dir);
}
