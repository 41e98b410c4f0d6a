// A participant's trial list: every block's practice trials first, then its conditions ×
// repetitions in a seeded pseudo-random order, with breaks — the same list again from the same
// seed, so a resumed session continues the order it began.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/study_file.h"

namespace palpa::host {

struct ScheduledTrial {
  int index = 0;       ///< 0-based over the whole session, the records' "index"
  int block = 0;       ///< into Study::blocks
  int condition = -1;  ///< into Study::conditions; -1 for a staircase trial (adaptive)
  bool practice = false;
  bool break_before = false;  ///< the participant rests before this trial
  /// Staircase: true when the comparison goes on the staircase's second finger.
  bool comparison_second = false;
};

struct StudyPlan {
  uint64_t seed = 0;
  std::vector<ScheduledTrial> trials;
};

/// The seed for a participant in a study: a hash of the study as run (StudyToJson) and the id,
/// below 2^53 so that JSON carries it exactly.
uint64_t StudySeed(const Study& study, const std::string& participant);
/// The plan from a seed. A staircase block gets max_trials entries; the runner ends it early
/// once its reversals are in.
StudyPlan PlanStudy(const Study& study, uint64_t seed);
/// The plan as session.json's "order": {"index", "block" (name), "condition" (name, or
/// "staircase"), "practice", "break_before"}.
nlohmann::ordered_json PlanToJson(const Study& study, const StudyPlan& plan);

}  // namespace palpa::host
