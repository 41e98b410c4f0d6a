// Answers: typed as people count fingers (from 1), checked against the trial's question.
#include <algorithm>
#include <cctype>
#include <sstream>

#include "palpa/host/request_text.h"
#include "palpa/host/study_runner.h"

namespace palpa::host {

Outcome CheckAnswer(const TrialPrompt& trial, const StudyAnswer& a) {
  if (a.fingers.size() != static_cast<size_t>(trial.fingers)) {
    return Outcome::Fail(Status::kInvalidArgument,
                         "the answer has " + std::to_string(a.fingers.size()) +
                             " finger flags, the study " + std::to_string(trial.fingers));
  }
  const long marked = std::count(a.fingers.begin(), a.fingers.end(), true);
  if (trial.kind == BlockKind::kStaircase) {
    const bool one_compared =
        marked == 1 && std::any_of(trial.compared.begin(), trial.compared.end(),
                                   [&](int f) { return a.fingers[static_cast<size_t>(f)]; });
    if (!a.tumour || !one_compared) {
      return Outcome::Fail(
          Status::kInvalidArgument,
          "say which finger felt stiffer: " + std::to_string(trial.compared[0] + 1) + " or " +
              std::to_string(trial.compared[1] + 1));
    }
    return {};
  }
  if (!a.tumour && marked > 0)
    return Outcome::Fail(Status::kInvalidArgument, "no tumour, yet fingers are marked");
  if (a.tumour && marked == 0)
    return Outcome::Fail(Status::kInvalidArgument, "a tumour, but under no finger");
  if (a.tumour && marked == trial.fingers && trial.fingers > 1)
    return Outcome::Fail(Status::kInvalidArgument,
                         "a tumour under every finger is no tumour (all equal): answer n");
  return {};
}

Result<StudyAnswer> ParseAnswerText(const TrialPrompt& trial, const std::string& text) {
  StudyAnswer a;
  a.fingers.assign(static_cast<size_t>(trial.fingers), false);
  std::string words = text;
  std::replace(words.begin(), words.end(), ',', ' ');
  std::istringstream in(words);
  std::string word;
  std::vector<std::string> parts;
  while (in >> word) parts.push_back(word);
  const std::string expected = trial.kind == BlockKind::kStaircase
                                   ? "the stiffer finger's number"
                                   : "n for no tumour, or the fingers' numbers (1 to " +
                                         std::to_string(trial.fingers) + "), e.g. \"2\" or \"1 2\"";
  if (parts.empty()) return {Status::kInvalidArgument, "no answer: type " + expected};
  if (parts.size() == 1 && (parts[0] == "n" || parts[0] == "N")) {
    if (trial.kind == BlockKind::kStaircase)
      return {Status::kInvalidArgument, "\"n\": type " + expected};
    return a;
  }
  for (const std::string& p : parts) {
    double v = 0;
    if (!ParseDecimal(p, v) || v != static_cast<int>(v) || v < 1 || v > trial.fingers)
      return {Status::kInvalidArgument, "\"" + p + "\": type " + expected};
    if (a.fingers[static_cast<size_t>(v) - 1])
      return {Status::kInvalidArgument, "finger " + p + " twice"};
    a.fingers[static_cast<size_t>(v) - 1] = true;
  }
  a.tumour = true;
  if (const Outcome o = CheckAnswer(trial, a); !o.ok()) return o;
  return a;
}

}  // namespace palpa::host
