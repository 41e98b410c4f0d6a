// palpa study: show and its refusals, and a session killed with SIGKILL mid-way and resumed — the
// records whole, every planned trial once, in the planned order.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli_run.h"

using palpa::testing::ExpectUsage;
using palpa::testing::Has;
using palpa::testing::OwnTempPath;
using palpa::testing::Palpa;

namespace fs = std::filesystem;

namespace {

/// Nine trials: three conditions twice at once, then once each finger in turn.
const char kStudy[] = PALPA_TEST_DATA_DIR "/study_short.json";

size_t Lines(const std::string& path) {
  std::ifstream in(path);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

/// `palpa ARGS` as a child of this process (exec'd, so its pid is palpa's).
pid_t Start(const std::string& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string command =
        std::string("exec env -u PALPA_DEVICE PALPA_STATE_DIR=/nonexistent ") + PALPA_CLI_PATH +
        " " + args + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

}  // namespace

TEST_GROUP(CliStudy){};

TEST(CliStudy, ShowPrintsTheResolvedStudyAndNamesABadField) {
  const auto shown = Palpa("--json study show thesis-pneumatic");
  LONGS_EQUAL_TEXT(0, shown.code, shown.output.c_str());
  const auto j = nlohmann::json::parse(shown.output);
  LONGS_EQUAL(14, j["conditions"].size());
  STRCMP_EQUAL("sequential", j["blocks"][0]["mode"].get<std::string>().c_str());
  const std::string bad = OwnTempPath("bad-study.json");
  std::stringstream text;
  text << std::ifstream(kStudy).rdbuf();
  std::string edited = text.str();
  edited.replace(edited.find("\"repetitions\": 2"), 16, "\"repetitions\": -1");
  std::ofstream(bad) << edited;
  const auto refused = Palpa("study show " + bad);
  LONGS_EQUAL(2, refused.code);
  CHECK_TEXT(Has(refused, "line 8: blocks[0].repetitions"), refused.output.c_str());
  fs::remove(bad);
  ExpectUsage("study run thesis-pneumatic --out /tmp/x", "--participant ID is missing");
  // A bad id is a usage error, refused before any board is started.
  ExpectUsage("study run thesis-pneumatic --participant ../P1 --out /tmp/x",
              "participant \"../P1\": 1 to 64 letters");
  ExpectUsage(
      "study run thesis-pneumatic --participant P1 --out /tmp/x --device tcp:127.0.0.1:1 "
      "--simulated-participant 1",
      "a sim: device only");
  // A trigger line that is not there refuses the run before a board is started or DIR made (the
  // line's pulses are tested on a real kernel's gpio-mockup: tests/kernel/gpio).
  const std::string out = OwnTempPath("study-no-line");
  fs::remove_all(out);
  const auto no_line = Palpa("study run thesis-pneumatic --participant P1 --out " + out +
                             " --simulated-participant 1 --trigger-gpio nochip:0");
  LONGS_EQUAL(1, no_line.code);
  CHECK_TEXT(Has(no_line, "--trigger-gpio 'nochip:0': no GPIO chip 'nochip'"),
             no_line.output.c_str());
  CHECK_FALSE(fs::exists(out));
}

TEST(CliStudy, KilledMidSessionAndResumed) {
  const std::string dir = OwnTempPath("study-P07");
  fs::remove_all(dir);
  const std::string run = std::string("study run ") + kStudy + " --participant P07 --out " + dir +
                          " --device sim:thesis-pneumatic-3 --speed 10 --simulated-participant 3";
  const pid_t child = Start(run);
  // SIGKILL once three trials are in: no chance to close anything.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (Lines(dir + "/trials.jsonl") < 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  CHECK(WIFSIGNALED(status));
  const size_t kept = Lines(dir + "/trials.jsonl");
  CHECK_TEXT(kept >= 3 && kept < 9, std::to_string(kept).c_str());

  // The same participant again without --resume: refused, nothing touched.
  const auto reused = Palpa(run);
  LONGS_EQUAL(1, reused.code);
  CHECK_TEXT(Has(reused, "already holds an incomplete session of participant P07"),
             reused.output.c_str());
  LONGS_EQUAL(kept, Lines(dir + "/trials.jsonl"));

  const auto resumed = Palpa(run + " --resume");
  LONGS_EQUAL_TEXT(0, resumed.code, resumed.output.c_str());
  std::ifstream in(dir + "/session.json");
  const auto session = nlohmann::json::parse(in);
  CHECK(session["complete"].get<bool>());
  LONGS_EQUAL(1, session["resumed"].size());
  LONGS_EQUAL(1, session["provenance"]["sim"]["seed"].get<int>());
  std::ifstream trials(dir + "/trials.jsonl");
  std::set<int> seen;
  int i = 0;
  for (std::string line; std::getline(trials, line); ++i) {
    const auto t = nlohmann::json::parse(line);  // every line whole
    LONGS_EQUAL(i, t["index"].get<int>());       // in the planned order, none twice
    CHECK(seen.insert(t["index"].get<int>()).second);
    CHECK(session["order"][i]["condition"] == t["condition"]);
  }
  LONGS_EQUAL(9, i);
  fs::remove_all(dir);
}

TEST(CliStudy, AnswersTypedAtTheTerminalAndABadOneAskedAgain) {
  const std::string file = OwnTempPath("one-trial.json");
  const std::string dir = OwnTempPath("study-T1");
  fs::remove_all(dir);
  std::ofstream(file) << R"({"schema": "palpa-study", "schema_version": 1, "name": "one",
    "finger_kind": "pneumatic", "fingers": 3, "unit": "kPa", "cap_kpa": 40,
    "reset": {"hold_ms": 100}, "conditions": [{"values": [0, 30, 0]}],
    "blocks": [{"name": "b", "mode": "simultaneous"}]})";
  const auto r = palpa::testing::Shell(
      std::string("printf '4\\n1 2 3\\n2\\n' | env -u PALPA_DEVICE ") + PALPA_CLI_PATH +
      " study run " + file + " --participant T1 --out " + dir + " --speed 10");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "\"4\": type n for no tumour, or the fingers' numbers (1 to 3)"),
             r.output.c_str());
  CHECK_TEXT(Has(r, "a tumour under every finger is no tumour"), r.output.c_str());
  std::ifstream in(dir + "/trials.jsonl");
  std::string line;
  CHECK(static_cast<bool>(std::getline(in, line)));
  const auto t = nlohmann::json::parse(line);
  CHECK(t["answer"]["fingers"] == nlohmann::json({false, true, false}));
  CHECK(t["expected"] == nlohmann::json({false, true, false}));
  fs::remove_all(dir);
  fs::remove(file);
}
