// Study records read from JSON: every field of session.json and of a trials.jsonl line checked
// and named in the error; fields a later version of the format added are kept, not refused.
#include "palpa/host/study_records.h"

#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string_view>

#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

using nlohmann::json;

/// Most finger positions a trial can have (boards have at most 8 fingers; room to spare).
constexpr size_t kMaxPositions = 16;
/// Board-clock milliseconds and trial indices: integers far from any double's rounding.
constexpr long kMaxCount = 1L << 50;
/// Planned trials per session: far beyond what a participant sits through.
constexpr size_t kMaxTrialsPlanned = 100000;

/// The keys of `j` that `known` names, as an object to validate; the others into *extra (fields a
/// later version of the format added).
json Known(const json& j, const std::string& path, const std::set<std::string>& known,
           json* extra) {
  if (!j.is_object()) throw JsonInvalid((path.empty() ? "document" : path) + ": must be an object");
  json mine = json::object();
  for (auto it = j.begin(); it != j.end(); ++it) {
    (known.count(it.key()) ? mine : *extra)[it.key()] = it.value();
  }
  return mine;
}

std::vector<bool> Flags(const JsonObject& o, const char* key, size_t lo, size_t hi) {
  const json& list = o.List(key, lo, hi);
  std::vector<bool> out;
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_boolean()) throw JsonInvalid(o.Item(key, i) + ": must be true or false");
    out.push_back(list[i].get<bool>());
  }
  return out;
}

uint64_t Unsigned(const JsonObject& o, const char* key) {
  const json& v = o.At(key);
  if (!v.is_number_unsigned()) throw JsonInvalid(o.Join(key) + ": must be an integer, 0 or more");
  return v.get<uint64_t>();
}

bool AllHex(const std::string& s, size_t from) {
  for (size_t i = from; i < s.size(); ++i) {
    if (!std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return s.size() > from;
}

/// "YYYY-MM-DDTHH:MM:SS", optional fraction, "Z".
std::string Utc(const JsonObject& o, const char* key) {
  const std::string t = o.Text(key);
  constexpr std::string_view shape = "dddd-dd-ddTdd:dd:dd";
  bool ok = t.size() > shape.size() && t.back() == 'Z';
  for (size_t i = 0; ok && i < shape.size(); ++i) {
    ok = shape[i] == 'd' ? std::isdigit(static_cast<unsigned char>(t[i])) != 0 : t[i] == shape[i];
  }
  if (ok && t.size() > shape.size() + 1) {
    ok = t[shape.size()] == '.' && t.size() > shape.size() + 2;
    for (size_t i = shape.size() + 1; ok && i + 1 < t.size(); ++i)
      ok = std::isdigit(static_cast<unsigned char>(t[i])) != 0;
  }
  if (!ok)
    throw JsonInvalid(o.Join(key) + ": \"" + t + "\" is not a UTC time like " +
                      "2026-11-26T18:00:00Z");
  return t;
}

StudyProvenance ParseProvenance(const json& j) {
  StudyProvenance p;
  const std::set<std::string> fields = {"palpa_version",
                                        "firmware_version",
                                        "catalog_hash",
                                        "config_crc",
                                        "calibration_files",
                                        "board",
                                        "sim"};
  const json known = Known(j, "provenance", fields, &p.extra);
  const JsonObject o(known, "provenance", fields);
  p.palpa_version = o.Text("palpa_version");
  p.firmware_version = o.Text("firmware_version");
  p.catalog_hash = o.Text("catalog_hash");
  p.config_crc = o.Text("config_crc");
  if (p.config_crc.rfind("0x", 0) != 0 || p.config_crc.size() > 10 || !AllHex(p.config_crc, 2))
    throw JsonInvalid("provenance.config_crc: \"" + p.config_crc +
                      "\" is not 0x and 1 … 8 hex digits");
  const json& files = o.At("calibration_files");
  if (!files.is_object()) throw JsonInvalid("provenance.calibration_files: must be an object");
  for (auto it = files.begin(); it != files.end(); ++it) {
    const std::string where = "provenance.calibration_files." + it.key();
    if (!it.value().is_string() || it.value().get<std::string>().size() != 64 ||
        !AllHex(it.value().get<std::string>(), 0))
      throw JsonInvalid(where + ": must be a SHA-256 in 64 hex digits");
    p.calibration_files[it.key()] = it.value().get<std::string>();
  }
  p.board = o.Text("board");
  if (!known.contains("sim")) throw JsonInvalid("provenance.sim: missing (null on a real board)");
  if (o.Has("sim")) {
    const JsonObject s(o.At("sim"), "provenance.sim", {"seed", "unit"});
    p.sim = SimProvenance{Unsigned(s, "seed"), s.Integer("unit", 0, kMaxCount)};
  }
  return p;
}

StudySession ParseSession(const json& j) {
  StudySession s;
  const std::set<std::string> fields = {"format",      "study",        "participant",
                                        "seed",        "order",        "provenance",
                                        "started_utc", "finished_utc", "complete"};
  const json known = Known(j, "", fields, &s.extra);
  const JsonObject o(known, "", fields);
  if (o.Text("format") != kStudySessionFormat)
    throw JsonInvalid(std::string("format: \"") + o.Text("format") + "\" is not " +
                      kStudySessionFormat);
  s.study = o.At("study");
  if (!s.study.is_object()) throw JsonInvalid("study: must be an object");
  if (!s.study.contains("name") || !s.study["name"].is_string() ||
      s.study["name"].get<std::string>().empty())
    throw JsonInvalid("study.name: must be a non-empty string");
  s.participant = o.Text("participant");
  s.seed = Unsigned(o, "seed");
  const json& order = o.List("order", 0, kMaxTrialsPlanned);
  std::set<int64_t> seen;
  for (size_t i = 0; i < order.size(); ++i) {
    const JsonObject e(order[i], o.Item("order", i), {"index", "block", "condition", "practice"});
    PlannedTrial p{e.Integer("index", 0, kMaxCount), e.Text("block"), e.Text("condition"),
                   e.Flag("practice")};
    if (!seen.insert(p.index).second)
      throw JsonInvalid(e.Join("index") + ": " + std::to_string(p.index) + " is planned twice");
    s.order.push_back(p);
  }
  s.provenance = ParseProvenance(o.At("provenance"));
  s.started_utc = Utc(o, "started_utc");
  if (!known.contains("finished_utc"))
    throw JsonInvalid("finished_utc: missing (null while the session runs)");
  if (o.Has("finished_utc")) s.finished_utc = Utc(o, "finished_utc");
  s.complete = o.Flag("complete");
  if (s.complete && !s.finished_utc) throw JsonInvalid("complete: true, but finished_utc is null");
  return s;
}

TrialRecord ParseTrial(const json& j) {
  TrialRecord t;
  const std::set<std::string> fields = {
      "index", "block",    "mode",   "practice", "condition",        "stimulus",
      "unit",  "expected", "answer", "time_ms",  "settled_board_ms", "answered_board_ms",
      "kind",  "staircase"};
  const json known = Known(j, "", fields, &t.extra);
  const JsonObject o(known, "", fields);
  t.kind = o.Choice("kind", {"detection", "staircase"}) == "detection" ? TrialKind::kDetection
                                                                       : TrialKind::kStaircase;
  const bool detection = t.kind == TrialKind::kDetection;
  t.index = o.Integer("index", 0, kMaxCount);
  t.block = o.Text("block");
  t.practice = o.Flag("practice");
  if (detection || o.Has("mode")) {
    t.mode = o.Choice("mode", {"simultaneous", "sequential"}) == "simultaneous"
                 ? TrialMode::kSimultaneous
                 : TrialMode::kSequential;
  }
  if (detection || o.Has("condition")) t.condition = o.Text("condition");
  const char* other[] = {"stimulus", "unit", "expected", "answer"};
  if (detection) {
    const json& stimulus = o.List("stimulus", 1, kMaxPositions);
    for (size_t i = 0; i < stimulus.size(); ++i) {
      if (!stimulus[i].is_number() || !std::isfinite(stimulus[i].get<double>()))
        throw JsonInvalid(o.Item("stimulus", i) + ": must be a number");
      t.stimulus.push_back(stimulus[i].get<double>());
    }
    const size_t n = t.stimulus.size();
    t.unit = o.Text("unit");
    t.expected = Flags(o, "expected", n, n);
    const JsonObject a(o.At("answer"), "answer", {"tumour", "fingers"});
    t.answer.tumour = a.Flag("tumour");
    t.answer.fingers = Flags(a, "fingers", n, n);
    for (size_t i = 0; i < n; ++i) {
      if (!t.answer.tumour && t.answer.fingers[i])
        throw JsonInvalid(a.Item("fingers", i) + ": marked, but answer.tumour is false");
    }
    if (o.Has("staircase")) throw JsonInvalid("staircase: only a staircase trial has one");
  } else {
    for (const char* key : other) {
      if (o.Has(key)) throw JsonInvalid(std::string(key) + ": a staircase trial has none");
    }
    const JsonObject s(o.At("staircase"), "staircase",
                       {"reference", "comparison", "unit", "correct", "reversal"});
    t.staircase = {s.Number("reference", -1e12, 1e12), s.Number("comparison", -1e12, 1e12),
                   s.Text("unit"), s.Flag("correct"), s.Flag("reversal")};
  }
  t.time_ms = o.Integer("time_ms", 0, kMaxCount);
  t.settled_board_ms = o.Integer("settled_board_ms", 0, kMaxCount);
  t.answered_board_ms = o.Integer("answered_board_ms", 0, kMaxCount);
  // The time is the difference of the two readings; a millisecond either way for rounding.
  if (std::llabs(t.answered_board_ms - t.settled_board_ms - t.time_ms) > 1)
    throw JsonInvalid("time_ms: " + std::to_string(t.time_ms) +
                      " is not answered_board_ms − settled_board_ms (" +
                      std::to_string(t.answered_board_ms - t.settled_board_ms) + ")");
  return t;
}

template <typename T, typename Parse>
Result<T> Checked(const json& j, Parse parse) {
  try {
    return parse(j);
  } catch (const JsonInvalid& e) {
    return Result<T>{Status::kInvalidArgument, e.what()};
  }
}

}  // namespace

Result<StudySession> SessionFromJson(const json& j) {
  return Checked<StudySession>(j, ParseSession);
}

Result<TrialRecord> TrialFromJson(const json& j) { return Checked<TrialRecord>(j, ParseTrial); }

}  // namespace palpa::host
