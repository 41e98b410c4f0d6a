// Recorded trajectories: the CSV header, then time, position and force per sample, checked line
// by line.
#include "palpa/host/scene_input.h"

#include <cstdio>

#include "number_text.h"
#include "palpa/host/scene_files.h"

namespace palpa::host {
namespace {

/// The header's names, spaces around each allowed.
bool IsHeader(std::string line) {
  std::string names;
  for (char c : line) {
    if (c != ' ' && c != '\t') names += c;
  }
  return names == kTrajectoryHeader;
}

}  // namespace

Result<std::vector<SceneInput>> ParseTrajectory(const std::string& text,
                                                const std::string& source) {
  using Samples = Result<std::vector<SceneInput>>;
  const auto lines = CsvDataLines(text);
  if (lines.empty() || !IsHeader(lines[0].second)) {
    return Samples(Status::kInvalidArgument,
                   source + ": line " + (lines.empty() ? "1" : std::to_string(lines[0].first)) +
                       ": expected the header " + kTrajectoryHeader);
  }
  if (lines.size() < 2) return Samples(Status::kInvalidArgument, source + ": no samples");
  if (lines.size() - 1 > kMaxTrajectorySamples) {
    return Samples(Status::kInvalidArgument,
                   source + ": more than " + std::to_string(kMaxTrajectorySamples) + " samples");
  }
  std::vector<SceneInput> samples;
  samples.reserve(lines.size() - 1);
  for (size_t k = 1; k < lines.size(); ++k) {
    const std::string where = source + ": line " + std::to_string(lines[k].first);
    const auto v = ParseCsvNumbers(lines[k].second, where, 4);
    if (!v.ok()) return v.outcome();
    if (v.value.size() != 4) {
      return Samples(Status::kInvalidArgument, where + ": " + std::to_string(v.value.size()) +
                                                   " values, expected 4 (" + kTrajectoryHeader +
                                                   ")");
    }
    const SceneInput s{v.value[0], v.value[1], v.value[2], v.value[3]};
    if (!samples.empty() && !(s.time_s > samples.back().time_s)) {
      return Samples(Status::kInvalidArgument, where + ": time " + Num(s.time_s) +
                                                   " s is not after line " +
                                                   std::to_string(lines[k - 1].first) + "'s " +
                                                   Num(samples.back().time_s) + " s");
    }
    if (!(s.force_n >= 0 && s.force_n <= kMaxInputForceN)) {
      return Samples(
          Status::kInvalidArgument,
          where + ": force " + Num(s.force_n) + " N is outside 0 … " + Num(kMaxInputForceN) + " N");
    }
    samples.push_back(s);
  }
  return samples;
}

Result<std::vector<SceneInput>> LoadTrajectory(const std::string& path) {
  const Result<std::string> text = ReadFileWhole(path, kTrajectoryLimits);
  if (!text.ok()) return text.outcome();
  return ParseTrajectory(text.value, path);
}

}  // namespace palpa::host
