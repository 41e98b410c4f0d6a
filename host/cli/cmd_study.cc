// palpa study: the built-in and custom discrimination studies — list, show, and run one session
// with the participant answering at the terminal (or a simulated participant on a simulated board).
#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>

#include "cli.h"
#include "palpa/host/file_write.h"
#include "palpa/host/sim_truth.h"
#include "palpa/host/study_participant.h"
#include "palpa/host/study_runner.h"
#include "palpa/host/transport.h"
#include "trigger_line.h"

namespace palpa::cli {

namespace {

using protocol::Status;

/// The participant at the terminal: told only the question, answers typed as people count.
class TerminalParticipant final : public host::StudyParticipant {
 public:
  void Feel(const host::TrialPrompt&, int finger, host::BoardClock& clock,
            double until_s) override {
    std::printf("  finger %d: feel it (Enter moves on)\n", finger + 1);
    std::fflush(stdout);
    while (clock.now_s() < until_s && !Interrupted()) {
      pollfd p{STDIN_FILENO, POLLIN, 0};
      if (poll(&p, 1, 50) > 0) {
        std::string line;
        if (!std::getline(std::cin, line)) return;
        return;
      }
    }
  }
  host::Result<host::StudyAnswer> Answer(const host::TrialPrompt& t, host::BoardClock&) override {
    for (;;) {
      std::printf("%s\n  (%s; q stops) > ", t.question.c_str(),
                  t.kind == host::BlockKind::kStaircase
                      ? "the finger's number"
                      : "n: no tumour; or the fingers' numbers, e.g. 2 or 1 2");
      std::fflush(stdout);
      std::string line;
      if (Interrupted() || !std::getline(std::cin, line) || line == "q")
        return {Status::kUnavailable, "stopped"};
      const auto a = host::ParseAnswerText(t, line);
      if (a.ok()) return a;
      std::printf("  %s\n", a.message.c_str());
    }
  }
  void Refused(const std::string& why) override { std::printf("  %s\n", why.c_str()); }
  bool Break(int done, int total) override {
    std::printf("Break: %d of %d trials done. Enter continues, q stops. ", done, total);
    std::fflush(stdout);
    std::string line;
    return std::getline(std::cin, line) && line != "q" && !Interrupted();
  }
};

int List() {
  for (const std::string& n : host::BuiltInStudies()) {
    const auto s = host::LoadStudy(n);
    std::fprintf(TextOut(), "%s: %s\n", n.c_str(),
                 s.ok() ? s.value.description.c_str() : s.message.c_str());
  }
  return kExitOk;
}

int Show(const std::vector<std::string>& args) {
  if (args.size() != 1)
    return Usage("study show", "expected one STUDY (a built-in name or a file)");
  const auto s = host::LoadStudy(args[0]);
  if (!s.ok()) return Fail("study show", s.status, s.message, kExitUsage);
  const nlohmann::ordered_json j = host::StudyToJson(s.value);
  if (JsonOutput()) {
    PrintJson(j);
  } else {
    std::printf("%s\n", j.dump(2).c_str());
  }
  return kExitOk;
}

struct RunArgs {
  std::string study, participant, out, device, calibration_dir, triggers, trigger_gpio;
  bool resume = false, nominal = false;
  std::string speed = "1";
  long simulated = -1;  ///< the simulated participant's seed; −1: the terminal
};

host::Result<RunArgs> ParseRun(const std::vector<std::string>& args) {
  RunArgs r;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--resume" || a == "--nominal-only") {
      (a == "--resume" ? r.resume : r.nominal) = true;
      continue;
    }
    if (a.rfind("--", 0) != 0) {
      if (!r.study.empty()) return {Status::kInvalidArgument, "unexpected argument '" + a + "'"};
      r.study = a;
      continue;
    }
    const auto v = OptionValue(args, i++);
    if (!v.ok()) return v.outcome();
    double n = 0;
    if (a == "--participant") {
      r.participant = v.value;
    } else if (a == "--out") {
      r.out = v.value;
    } else if (a == "--device") {
      r.device = v.value;
    } else if (a == "--calibration-dir") {
      r.calibration_dir = v.value;
    } else if (a == "--triggers") {
      r.triggers = v.value;
    } else if (a == "--trigger-gpio") {
      r.trigger_gpio = v.value;
    } else if (a == "--speed") {
      if (!ParseNumber(v.value, n) || n < 0.1 || n > 100)
        return {Status::kInvalidArgument, "--speed " + v.value + ": 0.1 to 100"};
      r.speed = v.value;
    } else if (a == "--simulated-participant") {
      if (!ParseNumber(v.value, n) || n < 0 || n > 4294967295.0 || n != static_cast<long>(n))
        return {Status::kInvalidArgument,
                "--simulated-participant " + v.value + ": a seed, 0 or more"};
      r.simulated = static_cast<long>(n);
    } else {
      const std::string near = Suggest(a, {"--participant", "--out", "--device", "--resume",
                                           "--calibration-dir", "--nominal-only", "--triggers",
                                           "--trigger-gpio", "--speed", "--simulated-participant"});
      return {Status::kInvalidArgument,
              "unknown option '" + a + "'" + (near.empty() ? "" : " (did you mean " + near + "?)")};
    }
  }
  if (r.study.empty()) return {Status::kInvalidArgument, "a STUDY is missing"};
  if (r.participant.empty()) return {Status::kInvalidArgument, "--participant ID is missing"};
  if (const host::Outcome id = host::CheckParticipant(r.participant); !id.ok())
    return {id.status, id.message};
  if (r.out.empty()) return {Status::kInvalidArgument, "--out DIR is missing"};
  return r;
}

int Run(Context& c, const std::vector<std::string>& args) {
  const std::string cmd = "study run";
  const auto r = ParseRun(args);
  if (!r.ok()) return Usage(cmd, r.message);
  const auto study = host::LoadStudy(r.value.study);
  if (!study.ok()) return Fail(cmd, study.status, study.message, kExitUsage);
  const host::Study& s = study.value;
  std::string uri = r.value.device.empty() ? c.device_uri : r.value.device;
  if (r.value.device.empty() && c.device_defaulted) {  // a board the study fits
    uri = s.finger_kind == protocol::FingerKind::kJamming ? "sim:thesis-jamming-2"
                                                          : "sim:thesis-pneumatic-3";
  }
  c.device_uri = uri;  // what the closing message names
  // The trigger line is taken before the board starts: a missing or busy line refuses the run.
  std::shared_ptr<TriggerLine> trigger_line;
  if (!r.value.trigger_gpio.empty()) {
    auto opened = TriggerLine::Open(r.value.trigger_gpio);
    if (!opened.ok()) return Fail(cmd, opened.status, opened.message);
    trigger_line = opened.value;
  }
  const bool sim = uri == "sim" || uri.rfind("sim:", 0) == 0;
  if (r.value.simulated >= 0 && !sim)
    return Usage(cmd,
                 "--simulated-participant feels a simulated board's truth: a sim: device only");
  c.options.number_from = 1;
  c.options.levels.jamming_bias_kpa = s.finger_kind == protocol::FingerKind::kJamming
                                          ? s.bias_kpa
                                          : c.options.levels.jamming_bias_kpa;
  c.options.use_calibrations = !r.value.nominal;
  c.options.calibration_dir = r.value.calibration_dir;
  host::StudyRunOptions o;
  o.out_dir = r.value.out;
  o.participant = r.value.participant;
  o.resume = r.value.resume;
  o.board = uri;
  o.calibration_dir = r.value.calibration_dir;
  o.use_calibrations = !r.value.nominal;
  host::TruthReader truth;
  if (sim) {  // started here, so that its seed and unit go into the provenance
    std::string truth_address, announcement;
    auto t = host::LaunchSim(uri == "sim" ? "thesis-5finger" : uri.substr(4),
                             {"--speed", r.value.speed, "--truth-every-ms", "5"}, &truth_address,
                             nullptr, &announcement);
    if (!t.ok()) return Fail(cmd, t.status, "cannot start " + uri + ": " + t.message, kExitConnect);
    auto d = host::Device::Attach(std::move(t.value), c.options);
    if (!d.ok()) return Fail(cmd, d.status, uri + ": " + d.message, kExitConnect);
    c.device = std::move(d.value);
    c.closed_on_signal = std::make_unique<ClosedOnSignal>(c.device.get());
    if (r.value.simulated >= 0 && !truth.Connect(truth_address))
      return Fail(cmd, Status::kIoError, "cannot read the truth channel at " + truth_address,
                  kExitConnect);
    o.sim = host::SimProvenanceOf(announcement);
    if (!o.sim)
      return Fail(cmd, Status::kIoError, "palpa-sim did not say its unit and seed: " + announcement,
                  kExitConnect);
  } else {
    if (c.Device() == nullptr) return kExitConnect;
  }
  if (!r.value.triggers.empty() || trigger_line != nullptr) {
    const std::string path = r.value.triggers;
    o.on_trigger = [path, trigger_line](const host::TriggerEvent& e) {
      if (trigger_line != nullptr)
        trigger_line->Pulse("palpa study");  // first: the edge is the moment
      if (path.empty()) return;
      const nlohmann::ordered_json j = {
          {"event", e.kind}, {"trial", e.trial}, {"board_ms", e.board_ms}};
      const host::Outcome written = host::AppendFileLine(path, j.dump() + "\n");
      if (!written.ok()) std::fprintf(stderr, "palpa study: %s\n", written.message.c_str());
    };
  }
  o.progress = [](const std::string& line) {
    if (line.empty() || line[0] != '{') {
      std::fprintf(stderr, "palpa study: %s\n", line.c_str());
      return;
    }
    const auto j = nlohmann::json::parse(line);  // the trial's record: no condition shown
    std::fprintf(stderr, "palpa study: trial %d done in %ld ms\n", j["index"].get<int>() + 1,
                 j["time_ms"].get<long>());
  };
  TerminalParticipant terminal;
  host::SimulatedParticipantOptions po;
  po.seed = static_cast<uint32_t>(r.value.simulated);
  host::SimulatedParticipant simulated(truth, po);
  host::StudyParticipant& participant =
      r.value.simulated >= 0 ? static_cast<host::StudyParticipant&>(simulated) : terminal;
  const host::Outcome done = host::RunStudy(*c.device, s, participant, o);
  if (!done.ok()) return Fail(cmd, done.status, done.message);
  std::fprintf(TextOut(), "palpa study: %s complete in %s\n", o.participant.c_str(),
               o.out_dir.c_str());
  return kExitOk;
}

int CmdList(Context&, const std::vector<std::string>&) { return List(); }
int CmdShow(Context&, const std::vector<std::string>& args) { return Show(args); }

struct Subcommand {
  const char* name;
  int (*run)(Context&, const std::vector<std::string>&);
};

/// The analysis, `study report`, lives in cmd_study_report.cc.
const Subcommand kSubcommands[] = {
    {"list", CmdList}, {"show", CmdShow}, {"run", Run}, {"report", CmdStudyReport}};

int CmdStudy(Context& c, const std::vector<std::string>& args) {
  std::vector<std::string> names;
  for (const Subcommand& s : kSubcommands) names.push_back(s.name);
  if (args.empty()) return Usage("study", "a subcommand is missing: list, show, run or report");
  for (const Subcommand& s : kSubcommands) {
    if (args[0] == s.name) return s.run(c, {args.begin() + 1, args.end()});
  }
  const std::string near = Suggest(args[0], names);
  return Usage("study", "unknown subcommand '" + args[0] + "'" +
                            (near.empty() ? " (list, show, run or report)"
                                          : " (did you mean '" + near + "'?)"));
}

}  // namespace

const Command kStudyCommand{
    "study",
    "study list | show STUDY | run STUDY --participant ID --out DIR [--device URI] [--resume] "
    "[--calibration-dir DIR | --nominal-only] [--triggers FILE] [--trigger-gpio CHIP:LINE] "
    "[--speed X] "
    "[--simulated-participant SEED] | report DIR... [--out OUT]",
    "Discrimination studies (docs/studies.md): the thesis's two built in (thesis-pneumatic,\n"
    "thesis-jamming) or a study file. show prints a study resolved, every default filled in.\n"
    "run plays one participant's session: each trial reset and approached from below, set in\n"
    "one frame, timed from the moment the display settled on the board's clock; the participant\n"
    "answers at the terminal (n: no tumour; finger numbers from 1). DIR gets session.json and\n"
    "trials.jsonl, a line per trial as it ends: a killed session loses at most the trial in\n"
    "progress, and --resume continues it in the same order. A participant's DIR is used once.\n"
    "On a sim: device (started here, at --speed X) --simulated-participant SEED answers instead.\n"
    "--triggers FILE appends each trial's settled and answered events (board time) as JSON lines;\n"
    "--trigger-gpio CHIP:LINE pulses a GPIO line (libgpiod) high for 10 ms at each of them.\n"
    "report analyses the sessions of one study (each DIR a session's directory) as the thesis\n"
    "analysed its studies, pooling the participants: Se, Sp, PPV and ACC per block, mode,\n"
    "condition and participant with Wilson intervals (each finger position of each non-practice\n"
    "detection trial counted once), the two modes compared by the combined interval, Wilcoxon on\n"
    "the participants and t-tests on trial times, staircase JNDs, and every session's\n"
    "provenance. Writes OUT/report.html (SVG charts, no scripts) and a CSV file per table; OUT\n"
    "(default STUDY-report) is created if missing. Sessions of different studies, or one\n"
    "participant twice, are refused.",
    CmdStudy};

}  // namespace palpa::cli
