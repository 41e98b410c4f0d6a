// One trial: every finger reset and held, the stimulus set in one frame (or finger by finger,
// the others at the reset state), the trial clock started when the display has settled, the
// answer asked until it is a valid one, and the record the journal keeps.
#include <algorithm>
#include <cmath>

#include "number_text.h"
#include "study_session.h"

namespace palpa::host {
namespace {

/// Every finger to its value in one Set: one frame, every finger changing on the same tick. Never
/// once the session is stopping: the board was released for the participant.
Outcome SetAll(Device& device, const Study& study, const std::vector<double>& values,
               TelemetryClock& clock) {
  if (clock.stopped()) return Outcome::Fail(Status::kUnavailable, "stopped");
  std::vector<FingerRequest> requests;
  for (size_t f = 0; f < values.size(); ++f)
    requests.push_back({static_cast<uint8_t>(f), StudyRequest(study, values[f])});
  return device.Set(requests);
}

Result<double> ShowAndSettle(Device& device, const Study& study, const std::vector<double>& values,
                             TelemetryClock& clock) {
  if (const Outcome o = SetAll(device, study, values, clock); !o.ok()) return o;
  const std::optional<double> settled = clock.WaitSettled(study.settle_timeout_ms / 1000.0);
  if (clock.stopped()) return {Status::kUnavailable, "stopped"};
  if (!settled) {
    return {Status::kTimeout, "the display did not settle on " + ConditionName(values) + " " +
                                  study.unit + " within " +
                                  std::to_string(study.settle_timeout_ms) + " ms"};
  }
  return *settled;
}

long Ms(double s) { return std::lround(s * 1000); }

}  // namespace

bool StaircaseState::Answer(const Staircase& s, bool correct) {
  ++trials;
  int move = 0;
  if (correct) {
    streak_wrong = 0;
    if (++streak_correct >= s.down) move = -1, streak_correct = 0;  // harder
  } else {
    streak_correct = 0;
    if (++streak_wrong >= s.up) move = +1, streak_wrong = 0;  // easier
  }
  if (move == 0) return false;
  const bool reversal = last_move != 0 && move != last_move;
  if (reversal) ++reversals;
  last_move = move;
  // Never below one step, never easier than the start.
  difference = std::clamp(difference + move * s.step, s.step, std::fabs(s.start - s.reference));
  return reversal;
}

Result<TrialRecord> PlayTrial(Device& device, const Study& study, const ScheduledTrial& planned,
                              int total, StudyParticipant& participant, TelemetryClock& clock,
                              const StaircaseState* staircase, const StudyRunOptions& options) {
  const StudyBlock& block = study.blocks[static_cast<size_t>(planned.block)];
  const bool stairs = block.kind == BlockKind::kStaircase;
  TrialPrompt prompt;
  prompt.index = planned.index;
  prompt.total = total;
  prompt.block = block.name;
  prompt.question = study.question;
  prompt.mode = block.mode;
  prompt.kind = block.kind;
  prompt.practice = planned.practice;
  prompt.fingers = study.fingers;
  const double reset = ResetValue(study);
  std::vector<double> values(static_cast<size_t>(study.fingers), reset);
  std::vector<bool> expected(values.size(), false);
  int comparison_finger = -1;
  double comparison = 0;
  if (stairs) {
    const Staircase& s = block.staircase;
    prompt.compared = s.fingers;
    prompt.question = "Which finger is stiffer: " + std::to_string(s.fingers[0] + 1) + " or " +
                      std::to_string(s.fingers[1] + 1) + "?";
    comparison_finger = s.fingers[planned.comparison_second ? 1 : 0];
    const int reference_finger = s.fingers[planned.comparison_second ? 0 : 1];
    comparison = s.reference + (LargerIsStiffer(study) ? 1 : -1) * staircase->difference;
    values[static_cast<size_t>(comparison_finger)] = comparison;
    values[static_cast<size_t>(reference_finger)] = s.reference;
    expected[static_cast<size_t>(comparison_finger)] = true;
  } else {
    const StudyCondition& c = study.conditions[static_cast<size_t>(planned.condition)];
    values = c.values;
    for (int f : c.tumour) expected[static_cast<size_t>(f)] = true;
  }
  // Reset: hysteresis would otherwise carry the last trial into this one.
  if (const Outcome o = SetAll(device, study, std::vector<double>(values.size(), reset), clock);
      !o.ok())
    return o;
  clock.Wait(study.reset_ms / 1000.0);
  auto trigger = [&](const char* kind, double board_s) {
    if (options.on_trigger) options.on_trigger({kind, planned.index, board_s * 1000});
  };
  double settled = 0;
  nlohmann::json shown = nlohmann::json::array();
  if (block.mode == StudyMode::kSimultaneous) {
    const Result<double> s = ShowAndSettle(device, study, values, clock);
    if (!s.ok()) return s.outcome();
    settled = s.value;
    trigger("settled", settled);
  } else {
    for (size_t f = 0; f < values.size(); ++f) {
      std::vector<double> one(values.size(), reset);
      one[f] = values[f];
      const Result<double> s = ShowAndSettle(device, study, one, clock);
      if (!s.ok()) return s.outcome();
      if (f == 0) {
        settled = s.value;
        trigger("settled", settled);
      }
      shown.push_back(Ms(s.value));
      participant.Feel(prompt, static_cast<int>(f), clock, s.value + block.present_ms / 1000.0);
    }
    if (const Outcome o = SetAll(device, study, std::vector<double>(values.size(), reset), clock);
        !o.ok())
      return o;
  }
  StudyAnswer answer;
  for (;;) {
    Result<StudyAnswer> a = participant.Answer(prompt, clock);
    if (!a.ok()) return a.outcome();
    const Outcome check = CheckAnswer(prompt, a.value);
    if (check.ok()) {
      answer = a.value;
      break;
    }
    participant.Refused(check.message);
  }
  const double answered = clock.now_s();
  trigger("answered", answered);
  TrialRecord r;
  r.index = planned.index;
  r.block = block.name;
  r.mode = block.mode == StudyMode::kSequential ? TrialMode::kSequential : TrialMode::kSimultaneous;
  r.practice = planned.practice;
  r.condition =
      stairs ? "staircase" : study.conditions[static_cast<size_t>(planned.condition)].name;
  r.kind = stairs ? TrialKind::kStaircase : TrialKind::kDetection;
  r.stimulus = values;
  r.unit = study.unit;
  r.expected = expected;
  r.answer = {answer.tumour, answer.fingers};
  r.settled_board_ms = Ms(settled);
  r.answered_board_ms = Ms(answered);
  r.time_ms = r.answered_board_ms - r.settled_board_ms;
  if (!shown.empty()) r.extra["shown_board_ms"] = shown;  // sequential: each finger's settle
  if (stairs) {
    const bool correct = answer.fingers[static_cast<size_t>(comparison_finger)];
    StaircaseState next = *staircase;
    const bool reversal = !planned.practice && next.Answer(block.staircase, correct);
    r.staircase = {block.staircase.reference, comparison, study.unit, correct, reversal};
    r.extra["reversals_used"] = block.staircase.reversals_used;
    // Which finger showed what, and which the participant named: the record keeps no stimulus
    // or answer of its own for a staircase trial.
    r.extra["values"] = values;
    r.extra["marked"] = answer.fingers;
  }
  return r;
}

}  // namespace palpa::host
