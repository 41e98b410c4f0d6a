// A study's analysis from its sessions' records, as the thesis analysed its studies (§5.3.4,
// §5.4.4): detection metrics with Wilson intervals per block and per condition, the comparison of
// the two presentation modes (combined interval, Wilcoxon on participants, t-tests on trial
// times) and the staircase's JND per participant. The unit of analysis is each finger position of
// each non-practice detection trial; one time per trial (docs/studies.md, "Analysis").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/study_records.h"
#include "palpa/host/study_stats.h"

namespace palpa::host {

/// Counts and times of a set of detection trials.
struct DetectionTally {
  DetectionCounts counts;
  int trials = 0;
  std::vector<double> times_ms;  ///< one per trial
  void Add(const TrialRecord& t);
};

/// A block as run (its mode), pooled over participants.
struct BlockSummary {
  std::string block;
  TrialMode mode = TrialMode::kSimultaneous;
  DetectionTally tally;
};

/// A condition within a block, pooled over participants.
struct ConditionSummary {
  std::string block, condition;
  TrialMode mode = TrialMode::kSimultaneous;
  DetectionTally tally;
};

/// One participant's detection trials in one mode.
struct ParticipantMode {
  std::string participant;
  TrialMode mode = TrialMode::kSimultaneous;
  DetectionTally tally;
};

/// One metric compared between the two modes: sequential first, simultaneous second.
struct MetricComparison {
  std::string metric;  ///< "Se", "Sp", "PPV", "ACC"
  Proportion sequential, simultaneous;
  ProportionComparison by_own_n;     ///< each proportion over its own denominator
  ProportionComparison by_thesis_n;  ///< over every finger position, as the thesis's intervals
  WilcoxonResult participants;       ///< paired per-participant values
  int participants_paired = 0;       ///< participants with the metric defined in both modes
};

struct ModeComparison {
  std::vector<MetricComparison> metrics;  ///< Se, Sp, PPV, ACC
  int trials_sequential = 0, trials_simultaneous = 0;
  TTestResult times_welch;        ///< every trial's time, sequential against simultaneous
  TTestResult times_paired;       ///< per-participant mean times
  WilcoxonResult times_wilcoxon;  ///< per-participant mean times
  int participants_paired = 0;
};

/// A participant's staircase in one block.
struct StaircaseSummary {
  std::string participant, block, unit;
  int trials = 0, reversals = 0, reversals_used = 0;
  double jnd = 0;        ///< mean |comparison − reference| over the last reversals_used reversals
  double reference = 0;  ///< mean reference over those reversals
  double weber = 0;      ///< jnd / reference
  bool enough = false;   ///< at least reversals_used reversals (else the JND is over fewer)
  std::vector<std::pair<double, double>> track;  ///< trial number, comparison − reference
};

struct SessionSummary {
  size_t session = 0;  ///< its index in StudyAnalysis::sessions
  int detection_trials = 0, practice_trials = 0, staircase_trials = 0;
  std::vector<std::string> warnings;
};

struct StudyAnalysis {
  std::string study;
  std::vector<SessionRecords> sessions;  ///< as read, in the order given
  std::vector<SessionSummary> summaries;
  std::vector<BlockSummary> blocks;
  std::vector<ConditionSummary> conditions;
  std::vector<ParticipantMode> participant_modes;
  std::optional<ModeComparison> comparison;  ///< when both modes were run
  std::vector<StaircaseSummary> staircases;
  std::vector<std::string> notes;  ///< e.g. a session that did not complete
};

/// Pools the sessions of one study. Refused (invalid argument, naming both directories): sessions
/// of different studies, or of one study name run with different definitions, or one participant
/// twice; staircase trials whose block (study.blocks[i], by name) has no staircase.reversals_used.
Result<StudyAnalysis> AnalyseStudy(std::vector<SessionRecords> sessions);

}  // namespace palpa::host
