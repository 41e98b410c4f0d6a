// Study definitions: what a discrimination study presents, in which blocks and order, and what
// it asks — the thesis's two studies built in, custom studies read from a file whose errors name
// the field and its line (docs/studies.md).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/file_read.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::host {

inline constexpr FileLimits kStudyFileLimits{"study file", 256 * 1024};

/// How a block presents a condition: each finger in turn, the others vented (sequential: the
/// thesis's single-finger mode), or every finger at once in one frame (simultaneous).
enum class StudyMode { kSequential, kSimultaneous };
/// A detection trial asks whether there is a tumour and where; a staircase trial asks which of
/// two fingers is stiffer, the difference adapting to the answers.
enum class BlockKind { kDetection, kStaircase };

/// One condition: a value per finger (in the study's unit) and the fingers the tumour rule marks.
struct StudyCondition {
  std::string name;  ///< "10-30-10" unless the file names it
  std::vector<double> values;
  std::vector<int> tumour;  ///< 0-based; empty: no tumour
};

/// An adaptive staircase, `down`-down-`up`-up, on two fingers: the reference on one, the
/// reference plus the difference on the other (which side is random), the difference starting
/// at start − reference and moving by `step`.
struct Staircase {
  double reference = 0, start = 0, step = 0;
  int down = 2, up = 1;
  int reversals = 8;       ///< stop after this many reversals …
  int reversals_used = 6;  ///< … and estimate the JND as the mean difference of the last ones
  int max_trials = 60;     ///< … or after this many trials, whichever comes first
  std::vector<int> fingers = {0, 1};  ///< the two fingers compared (0-based)
};

struct StudyBlock {
  std::string name;
  BlockKind kind = BlockKind::kDetection;
  StudyMode mode = StudyMode::kSimultaneous;
  /// Sequential: how long each finger is shown (ms) unless the participant moves on sooner.
  int present_ms = 3000;
  int repetitions = 1;    ///< each condition this many times
  bool randomise = true;  ///< seeded pseudo-random order; false: the conditions' order
  int practice = 0;       ///< practice trials first (conditions drawn from the block, not scored)
  int break_every = 0;    ///< a break after every this many trials (0: none)
  Staircase staircase;    ///< kStaircase only
};

struct Study {
  std::string name, description;
  std::string question = "Is there a tumour? If so, under which fingers?";
  protocol::FingerKind finger_kind = protocol::FingerKind::kPneumatic;
  int fingers = 0;
  double bias_kpa = 0;  ///< jamming: the pneumatic chamber's bias during the study
  /// The unit of every value: "kPa", "mm", "N/mm", "level" (a level index: L0, L1, …) or
  /// "normalized" (0..1 of the finger's range).
  std::string unit = "kPa";
  /// No stimulus may need more than this drive (kPa, magnitude): checked on the file's values
  /// where they are pressures, and through the finger's curves before the first trial.
  double cap_kpa = 100;
  /// Each trial starts from every finger vented (0 in the study's unit; in N/mm the softest value
  /// the study shows) held reset_ms, so every target is approached from below (rising) — or,
  /// approach "above", from the study's stiffest value down. Hysteresis otherwise carries each
  /// trial into the next.
  bool approach_from_above = false;
  int reset_ms = 500;
  /// Settled: every driven line's outlet reading steady within tolerance_kpa for hold_ms, within
  /// band_kpa of its setpoint (a regulator's static error: the display's accuracy is the
  /// compensation's, not the clock's), and its chamber estimate (the calibrated chamber model)
  /// within tolerance_kpa of the outlet; a trial that does not settle within settle_timeout_ms
  /// fails.
  double tolerance_kpa = 0.5;
  double band_kpa = 3;
  int hold_ms = 100;
  int settle_timeout_ms = 8000;
  std::vector<StudyCondition> conditions;
  std::vector<StudyBlock> blocks;
  std::string source;  ///< "built in", or the file's path
};

/// The built-in studies: thesis-pneumatic (3 fingers, 0/10/30 kPa, 14 conditions, single-finger
/// and three-finger blocks) and thesis-jamming (2 fingers, 0/−10/−100 kPa at 20 kPa bias, 8
/// conditions, single-finger and two-finger blocks).
std::vector<std::string> BuiltInStudies();
/// A built-in study by name, or a file by path (a '/' or a .json name).
Result<Study> LoadStudy(const std::string& name_or_path);
/// A study document; a bad one is an invalid argument naming the field by its path and line
/// ("line 12: blocks[1].repetitions: ...").
Result<Study> ParseStudy(const std::string& text);
/// The study as run, every default filled in: what `palpa study show` prints and session.json
/// keeps. ParseStudy(StudyToJson(s).dump()) gives `s` back.
nlohmann::ordered_json StudyToJson(const Study& study);

/// "10-30-10" (values joined; "/" between them when any is negative).
std::string ConditionName(const std::vector<double>& values);
/// Whether a larger value is a stiffer stimulus in the study's unit (not for jamming in kPa:
/// deeper vacuum, more negative, is stiffer).
bool LargerIsStiffer(const Study& study);
/// The request a value stands for in the study's unit.
Request StudyRequest(const Study& study, double value);

}  // namespace palpa::host
