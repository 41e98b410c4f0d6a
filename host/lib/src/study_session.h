// A session's start (study_session.cc): checks of the board against the study, the lines whose
// settling starts the trial clock, and the provenance; the trial itself (study_trial.cc).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/study_runner.h"
#include "study_settle.h"

namespace palpa::host {

std::string UtcNow();
/// Every value a study shows (its conditions, its staircases' reference and start).
std::vector<double> StudyValues(const Study& study);
/// The state each trial starts from: vented, 0 in the study's unit (in N/mm, the softest value
/// the study shows) when targets are approached from below; the stiffest value it shows from
/// above.
double ResetValue(const Study& study);
/// The board has the study's fingers, of its kind, its bias, and every value within the cap.
Outcome CheckBoardForStudy(Device& device, const Study& study);
/// The lines of the study's fingers with their chamber models; *settle says which in words.
Result<std::vector<SettleLine>> StudyLines(Device& device, const Study& study,
                                           nlohmann::ordered_json* settle);
/// The board, firmware, configuration and calibrations the trials ran on; the settle rule's lines
/// and the curves in use go into its extra fields.
Result<StudyProvenance> Provenance(Device& device, const Study& study,
                                   const StudyRunOptions& options);

/// A staircase's state, replayed from its block's records.
struct StaircaseState {
  double difference = 0;
  int streak_correct = 0, streak_wrong = 0, last_move = 0, reversals = 0, trials = 0;
  bool done(const Staircase& s) const { return reversals >= s.reversals || trials >= s.max_trials; }
  /// One scored answer: returns whether it made a reversal.
  bool Answer(const Staircase& s, bool correct);
};

/// One trial played and answered: its record (the contract's fields), or why not (a cancelled
/// trial: kUnavailable).
Result<TrialRecord> PlayTrial(Device& device, const Study& study, const ScheduledTrial& planned,
                              int total, StudyParticipant& participant, TelemetryClock& clock,
                              const StaircaseState* staircase, const StudyRunOptions& options);

}  // namespace palpa::host
