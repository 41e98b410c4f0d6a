// Scene inputs: one sample of a hand on the tissue (where, how hard, when), and recorded
// trajectories of them read from CSV.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"

namespace palpa::host {

/// One sample of the input: where the hand is on the tissue and how hard it presses.
struct SceneInput {
  double time_s = 0;
  double x_mm = 0, y_mm = 0;
  double force_n = 0;
};

/// Ten minutes at 1 kHz is 600 000 samples, about 25 MiB of text.
inline constexpr FileLimits kTrajectoryLimits{"trajectory", 64 * 1024 * 1024};
inline constexpr size_t kMaxTrajectorySamples = 2'000'000;
/// An input's force is at most this (the thesis's tissue-damage threshold is 6 N; a pen tablet
/// saturates near 5 N).
inline constexpr double kMaxInputForceN = 100;

/// The header a trajectory starts with (after any '#' comment lines).
inline constexpr const char* kTrajectoryHeader = "time_s,x_mm,y_mm,force_n";

/// A recorded trajectory's text: the header, then one sample per line — time rising strictly,
/// positions finite (off the tissue is allowed: nothing is felt there), force 0 … 100 N; at least
/// one sample. `source` names the text in errors ("PATH: line 7: time 1.2 s is not after line 6's
/// 1.2 s").
Result<std::vector<SceneInput>> ParseTrajectory(const std::string& text, const std::string& source);
/// ParseTrajectory of a file read within kTrajectoryLimits.
Result<std::vector<SceneInput>> LoadTrajectory(const std::string& path);

}  // namespace palpa::host
