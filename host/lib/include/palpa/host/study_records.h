// A study session's records, as the runner writes them and the report reads them: session.json
// (the study as run, the planned order, provenance; written whole) and trials.jsonl (one line per
// finished trial, appended and flushed). Format "palpa-study-session/1" (docs/studies.md).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/file_read.h"

namespace palpa::host {

inline constexpr const char* kStudySessionFormat = "palpa-study-session/1";
inline constexpr const char* kSessionFileName = "session.json";
inline constexpr const char* kTrialsFileName = "trials.jsonl";
/// A session file holds the study and its planned order: thousands of trials fit in a few MiB.
inline constexpr FileLimits kSessionFileLimits{"study session file", 8 * 1024 * 1024};
/// A trial line is a few hundred bytes; 64 MiB is beyond any study a person sits through.
inline constexpr FileLimits kTrialsFileLimits{"study trials journal", 64 * 1024 * 1024};

/// On a simulated board: what makes its run repeatable.
struct SimProvenance {
  uint64_t seed = 0;
  int64_t unit = 0;
};

/// The seed and unit in palpa-sim's announcement ("palpa-sim: thesis-pneumatic-3, plant level 3,
/// unit 12, seed 1, speed 1x"), or in the description of a link to a palpa-sim started by the
/// library, which carries it; nullopt when either is missing.
std::optional<SimProvenance> SimProvenanceOf(const std::string& text);

/// What the trials were run with, so a result can be traced to a board, firmware and calibration.
struct StudyProvenance {
  std::string palpa_version, firmware_version, catalog_hash;
  std::string config_crc;                                ///< "0x" and hex digits
  std::map<std::string, std::string> calibration_files;  ///< name → SHA-256, 64 hex digits
  std::string board;                                     ///< "sim", "usb:…", …
  std::optional<SimProvenance> sim;                      ///< null on a real board
  nlohmann::json extra = nlohmann::json::object();       ///< as StudySession::extra
};

/// One entry of the planned order (the randomisation as drawn).
struct PlannedTrial {
  int64_t index = 0;
  std::string block, condition;
  bool practice = false;
};

/// session.json.
struct StudySession {
  nlohmann::json study = nlohmann::json::object();  ///< the definition as run; "name" required
  std::string participant;
  uint64_t seed = 0;
  std::vector<PlannedTrial> order;
  StudyProvenance provenance;
  std::string started_utc;                  ///< "YYYY-MM-DDTHH:MM:SS[.fff]Z"
  std::optional<std::string> finished_utc;  ///< null while the session runs
  bool complete = false;
  /// Fields a later version of the format added (by the rule: optional fields only): kept as read,
  /// written back unchanged.
  nlohmann::json extra = nlohmann::json::object();

  std::string StudyName() const { return study.at("name").get<std::string>(); }
};

enum class TrialKind { kDetection, kStaircase };
enum class TrialMode { kSimultaneous, kSequential };

struct TrialAnswer {
  bool tumour = false;
  std::vector<bool> fingers;  ///< the positions the participant marked
};

struct StaircaseStep {
  double reference = 0, comparison = 0;
  std::string unit;
  bool correct = false, reversal = false;
};

/// One line of trials.jsonl.
struct TrialRecord {
  int64_t index = 0;
  std::string block;
  std::optional<TrialMode> mode;  ///< every detection trial has one
  bool practice = false;
  std::optional<std::string> condition;  ///< every detection trial has one
  TrialKind kind = TrialKind::kDetection;
  // Detection: per finger position, all of one length.
  std::vector<double> stimulus;
  std::string unit;
  std::vector<bool> expected;  ///< a tumour at this position?
  TrialAnswer answer;
  // Staircase.
  StaircaseStep staircase;
  // Both: answer − settled on the board's clock.
  int64_t time_ms = 0, settled_board_ms = 0, answered_board_ms = 0;
  nlohmann::json extra = nlohmann::json::object();  ///< as StudySession::extra
};

/// A session directory read back.
struct SessionRecords {
  std::string dir;
  StudySession session;
  std::vector<TrialRecord> trials;    ///< in the journal's order
  std::vector<std::string> warnings;  ///< e.g. the torn last line ignored, with file and line
};

const char* TrialModeName(TrialMode m);  ///< "simultaneous", "sequential"

nlohmann::json SessionToJson(const StudySession& s);
nlohmann::json TrialToJson(const TrialRecord& t);
/// From a parsed document; an invalid argument naming the field by its path ("provenance.sim.seed:
/// must be …") on anything the format does not allow.
Result<StudySession> SessionFromJson(const nlohmann::json& j);
Result<TrialRecord> TrialFromJson(const nlohmann::json& j);
/// One line of trials.jsonl (no newline), as AppendTrial writes it.
std::string TrialLine(const TrialRecord& t);

/// Writes DIR/session.json whole (never half: a temporary renamed over it, flushed).
Outcome WriteSession(const std::string& dir, const StudySession& s);
/// Appends the trial to DIR/trials.jsonl and flushes it to disk before returning; a torn last line
/// an earlier crash left is cut off first (named in the outcome's notes).
Outcome AppendTrial(const std::string& dir, const TrialRecord& t);

/// Reads DIR/session.json and DIR/trials.jsonl (missing: no trials yet). A torn last line (no
/// newline) is ignored with a warning; any other malformed line is an invalid argument naming the
/// file, the line and the field ("DIR/trials.jsonl: line 7: answer.fingers[1]: …"), as is a
/// detection trial that is not in the planned order or does not match its entry there, or a trial
/// that repeats an index.
Result<SessionRecords> ReadSessionDir(const std::string& dir);

}  // namespace palpa::host
