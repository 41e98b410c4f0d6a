// Study session records written and read back: the session file written whole, trials appended a
// flushed line at a time, a session directory read back against its plan (the JSON checks of each
// record are study_records_parse.cc's).
#include "palpa/host/study_records.h"

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>

#include "palpa/host/file_write.h"
#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

using nlohmann::json;

json FlagsJson(const std::vector<bool>& flags) {
  json list = json::array();
  for (bool f : flags) list.push_back(f);
  return list;
}

/// The trial's checks against the session's plan; empty when it fits.
std::string AgainstPlan(const TrialRecord& t, const std::map<int64_t, PlannedTrial>& plan) {
  const auto it = plan.find(t.index);
  if (it == plan.end()) {
    return t.kind == TrialKind::kDetection
               ? "index: " + std::to_string(t.index) + " is not in session.json's order"
               : "";
  }
  const PlannedTrial& p = it->second;
  if (t.block != p.block)
    return "block: \"" + t.block + "\", but the order plans \"" + p.block + "\"";
  if (t.condition && *t.condition != p.condition)
    return "condition: \"" + *t.condition + "\", but the order plans \"" + p.condition + "\"";
  if (t.practice != p.practice)
    return std::string("practice: ") + (t.practice ? "true" : "false") + ", but the order plans " +
           (p.practice ? "true" : "false");
  return "";
}

}  // namespace

const char* TrialModeName(TrialMode m) {
  return m == TrialMode::kSimultaneous ? "simultaneous" : "sequential";
}

json SessionToJson(const StudySession& s) {
  json j = s.extra;
  j["format"] = kStudySessionFormat;
  j["study"] = s.study;
  j["participant"] = s.participant;
  j["seed"] = s.seed;
  json order = json::array();
  for (const PlannedTrial& p : s.order) {
    order.push_back({{"index", p.index},
                     {"block", p.block},
                     {"condition", p.condition},
                     {"practice", p.practice}});
  }
  j["order"] = order;
  const StudyProvenance& p = s.provenance;
  j["provenance"] = p.extra;
  j["provenance"].update(json{{"palpa_version", p.palpa_version},
                              {"firmware_version", p.firmware_version},
                              {"catalog_hash", p.catalog_hash},
                              {"config_crc", p.config_crc},
                              {"calibration_files", p.calibration_files},
                              {"board", p.board},
                              {"sim", nullptr}});
  if (p.sim) j["provenance"]["sim"] = {{"seed", p.sim->seed}, {"unit", p.sim->unit}};
  j["started_utc"] = s.started_utc;
  j["finished_utc"] = s.finished_utc ? json(*s.finished_utc) : json(nullptr);
  j["complete"] = s.complete;
  return j;
}

json TrialToJson(const TrialRecord& t) {
  json j = t.extra;
  j["index"] = t.index;
  j["block"] = t.block;
  if (t.mode) j["mode"] = TrialModeName(*t.mode);
  j["practice"] = t.practice;
  if (t.condition) j["condition"] = *t.condition;
  if (t.kind == TrialKind::kDetection) {
    j["kind"] = "detection";
    j["stimulus"] = t.stimulus;
    j["unit"] = t.unit;
    j["expected"] = FlagsJson(t.expected);
    j["answer"] = {{"tumour", t.answer.tumour}, {"fingers", FlagsJson(t.answer.fingers)}};
  } else {
    j["kind"] = "staircase";
    const StaircaseStep& s = t.staircase;
    j["staircase"] = {{"reference", s.reference},
                      {"comparison", s.comparison},
                      {"unit", s.unit},
                      {"correct", s.correct},
                      {"reversal", s.reversal}};
  }
  j["time_ms"] = t.time_ms;
  j["settled_board_ms"] = t.settled_board_ms;
  j["answered_board_ms"] = t.answered_board_ms;
  return j;
}

std::string TrialLine(const TrialRecord& t) { return TrialToJson(t).dump(); }

Outcome WriteSession(const std::string& dir, const StudySession& s) {
  return WriteFileWhole(dir + "/" + kSessionFileName, SessionToJson(s).dump(2) + "\n");
}

Outcome AppendTrial(const std::string& dir, const TrialRecord& t) {
  return AppendFileLine(dir + "/" + kTrialsFileName, TrialLine(t) + "\n");
}

Result<SessionRecords> ReadSessionDir(const std::string& dir) {
  SessionRecords r;
  r.dir = dir;
  const std::string session_path = dir + "/" + kSessionFileName;
  Result<StudySession> session = ReadAndParse(session_path, kSessionFileLimits,
                                              [](const std::string& text) -> Result<StudySession> {
                                                const Result<json> j = ParseJson(text);
                                                if (!j.ok()) return j.outcome();
                                                return SessionFromJson(j.value);
                                              });
  if (!session.ok()) return session.outcome();
  r.session = std::move(session.value);
  std::map<int64_t, PlannedTrial> plan;
  for (const PlannedTrial& p : r.session.order) plan[p.index] = p;

  const std::string trials_path = dir + "/" + kTrialsFileName;
  const Result<std::string> text = ReadFileWhole(trials_path, kTrialsFileLimits);
  if (text.status == Status::kNotFound) return r;
  if (!text.ok()) return text.outcome();
  std::map<int64_t, size_t> line_of;  // trial index → the line that recorded it
  size_t at = 0;
  for (size_t line = 1; at < text.value.size(); ++line) {
    const size_t end = text.value.find('\n', at);
    const std::string where = trials_path + ": line " + std::to_string(line) + ": ";
    if (end == std::string::npos) {
      r.warnings.push_back(where + "torn (no newline: the write was interrupted); ignored");
      break;
    }
    const std::string body = text.value.substr(at, end - at);
    at = end + 1;
    if (body.empty()) return Outcome::Fail(Status::kInvalidArgument, where + "empty line");
    const Result<json> j = ParseJson(body);
    if (!j.ok()) return Outcome::Fail(Status::kInvalidArgument, where + j.message);
    Result<TrialRecord> t = TrialFromJson(j.value);
    if (!t.ok()) return Outcome::Fail(Status::kInvalidArgument, where + t.message);
    if (const std::string wrong = AgainstPlan(t.value, plan); !wrong.empty())
      return Outcome::Fail(Status::kInvalidArgument, where + wrong);
    const auto [earlier, fresh] = line_of.emplace(t.value.index, line);
    if (!fresh) {
      return Outcome::Fail(Status::kInvalidArgument,
                           where + "index: trial " + std::to_string(t.value.index) +
                               " is recorded on line " + std::to_string(earlier->second) +
                               " already");
    }
    r.trials.push_back(std::move(t.value));
  }
  return r;
}

/// The decimal number after `word ` in text (the first such), if any.
static std::optional<uint64_t> SimNumberAfter(const std::string& text, const std::string& word) {
  for (size_t at = text.find(word + " "); at != std::string::npos;
       at = text.find(word + " ", at + 1)) {
    if (at > 0 && std::isalnum(static_cast<unsigned char>(text[at - 1]))) continue;
    const char* digits = text.c_str() + at + word.size() + 1;
    if (!std::isdigit(static_cast<unsigned char>(*digits))) continue;
    errno = 0;
    const unsigned long long value = std::strtoull(digits, nullptr, 10);
    if (errno == 0) return value;
  }
  return std::nullopt;
}

std::optional<SimProvenance> SimProvenanceOf(const std::string& text) {
  const auto unit = SimNumberAfter(text, "unit"), seed = SimNumberAfter(text, "seed");
  if (!unit || !seed || *unit > static_cast<uint64_t>(INT64_MAX)) return std::nullopt;
  return SimProvenance{*seed, static_cast<int64_t>(*unit)};
}

}  // namespace palpa::host
