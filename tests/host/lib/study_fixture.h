// Synthetic study sessions with known counts, for the analysis and the report's tests: the
// thesis's pneumatic study shape (3 fingers, 14 stimuli, a one-finger block run sequentially and
// a three-finger block run simultaneously, one practice trial each), its errors spread over the
// participants in turn so that every participant's figures can be worked out by hand.
#pragma once

#include <string>
#include <vector>

#include "palpa/host/study_records.h"

namespace palpa::testing {

/// Errors in one mode: positions with a tumour left unmarked (FN), without one marked (FP).
struct ModeErrors {
  int fn = 0, fp = 0;
};

/// The 14 stimuli's tumour positions (thesis-pneumatic-14: 13 positives, 29 negatives).
inline constexpr bool kStimuli14[14][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                           {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0},
                                           {0, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

inline host::StudySession StudySessionFor(const std::string& study, const std::string& who) {
  host::StudySession s;
  s.study = {{"name", study},
             {"blocks",
              {{{"name", "one-finger"}, {"kind", "detection"}},
               {{"name", "three-finger"}, {"kind", "detection"}},
               {{"name", "jnd"}, {"kind", "staircase"}, {"staircase", {{"reversals_used", 4}}}}}}};
  s.participant = who;
  s.seed = 1000 + who.size();
  s.provenance = {"0.9.0",
                  "1.4.0",
                  "c0ffee12",
                  "0x5eed",
                  {{"finger1.json", std::string(64, 'b')}},
                  "sim",
                  host::SimProvenance{7, 12},
                  {}};
  s.started_utc = "2026-11-26T18:00:00Z";
  s.finished_utc = "2026-11-26T18:40:00Z";
  s.complete = true;
  return s;
}

/// Participant `p` of `participants`: a practice trial and the 14 stimuli per block. Mode m's
/// errors go to participants in turn (participant p gets errors/participants, plus one when p <
/// errors % participants), each on its first positions of that kind. Times: sequential 6 s +
/// 0.1 s per stimulus + 50 ms per participant; simultaneous 2 s less, plus 10 ms × (p mod 3).
inline host::SessionRecords SimulatedSession(const std::string& study, int p, int participants,
                                             ModeErrors sequential, ModeErrors simultaneous) {
  host::SessionRecords r;
  r.dir = "P" + std::to_string(p + 1);
  r.session = StudySessionFor(study, r.dir);
  int64_t index = 0, clock = 1000;
  for (int mode = 0; mode < 2; ++mode) {
    const ModeErrors e = mode == 0 ? sequential : simultaneous;
    int fn = e.fn / participants + (p < e.fn % participants ? 1 : 0);
    int fp = e.fp / participants + (p < e.fp % participants ? 1 : 0);
    const std::string block = mode == 0 ? "one-finger" : "three-finger";
    for (int k = -1; k < 14; ++k) {  // -1: the practice trial
      const bool* row = kStimuli14[k < 0 ? 3 : k];
      const std::vector<bool> expected(row, row + 3);
      host::TrialRecord t;
      t.index = index++;
      t.block = block;
      t.mode = mode == 0 ? host::TrialMode::kSequential : host::TrialMode::kSimultaneous;
      t.practice = k < 0;
      t.condition = "s" + std::to_string(k < 0 ? 3 : k);
      for (bool x : expected) t.stimulus.push_back(x ? 30 : 0);
      t.unit = "kPa";
      t.expected = expected;
      t.answer.fingers = expected;
      if (k < 0) t.answer.fingers = {false, false, true};  // practice: wrong, and not counted
      for (size_t i = 0; k >= 0 && i < expected.size(); ++i) {
        if (expected[i] && fn > 0) {
          t.answer.fingers[i] = false;
          --fn;
        } else if (!expected[i] && fp > 0) {
          t.answer.fingers[i] = true;
          --fp;
        }
      }
      for (bool marked : t.answer.fingers) t.answer.tumour = t.answer.tumour || marked;
      t.time_ms = (mode == 0 ? 6000 : 4000 + 10 * (p % 3)) + 100 * (k < 0 ? 0 : k) + 50 * p;
      t.settled_board_ms = clock;
      t.answered_board_ms = clock + t.time_ms;
      clock += t.time_ms + 3000;
      r.session.order.push_back({t.index, t.block, *t.condition, t.practice});
      r.trials.push_back(t);
    }
  }
  return r;
}

/// The thesis-shaped study: 12 participants; sequential 18 FN and 21 FP (Se 138/156, Sp
/// 327/348), simultaneous 10 FN and 11 FP (Se 146/156, Sp 337/348).
inline std::vector<host::SessionRecords> ThesisShapedStudy(const std::string& study = "pneumatic") {
  std::vector<host::SessionRecords> sessions;
  for (int p = 0; p < 12; ++p)
    sessions.push_back(SimulatedSession(study, p, 12, {18, 21}, {10, 11}));
  return sessions;
}

/// Staircase trials for a session: reference 30 kPa, the comparison's differences in `track`,
/// the ones at `reversals` (0-based) marked as reversals.
inline void AddStaircase(host::SessionRecords& r, const std::vector<double>& track,
                         const std::vector<size_t>& reversals) {
  int64_t index = 1000;
  for (size_t i = 0; i < track.size(); ++i) {
    host::TrialRecord t;
    t.index = index++;
    t.block = "jnd";
    t.kind = host::TrialKind::kStaircase;
    const bool reversal = std::find(reversals.begin(), reversals.end(), i) != reversals.end();
    t.staircase = {30, 30 + track[i], "kPa", i % 2 == 0, reversal};
    t.time_ms = 1500;
    t.settled_board_ms = 100000 + 5000 * static_cast<int64_t>(i);
    t.answered_board_ms = t.settled_board_ms + 1500;
    r.trials.push_back(t);
  }
}

}  // namespace palpa::testing
