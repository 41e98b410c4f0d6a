// The hysteresis evidence: identification on one simulated unit, then the fixed branch-gap
// protocol and held-out input sets on another, scored on the truth channel. Used by the
// benchmark (full runs) and by the regime tests (short runs).
#pragma once

#include <string>
#include <vector>

#include "finger_rig.h"

namespace palpa::testing {

struct Method {
  std::string name;  ///< "none", "branch(12)", "pi(16)", "api(16)" ...
  protocol::CompensatorKind kind = protocol::CompensatorKind::kNone;
  int size = 0;  ///< operators, or branch points
};

/// none, branch(12), pi(4, 8, 16, 32), api(8, 16).
std::vector<Method> AllMethods();

struct Identified {
  std::vector<protocol::InversePoint> inverse;  ///< static inverse (mid-line) for every method
  std::vector<calibration::SweepSample> sweep;
  std::string error;
};

/// Runs the identification sweep on `rig` (raw mode, dwell per point).
Identified Identify(FingerRig& rig, const calibration::SweepPlan& plan, int dwell_ms);

/// Fits a method on the sweep; error set when it cannot.
calibration::HysteresisFit FitMethod(const Method& m, const Identified& id, double drive_max);

struct GapResult {
  double major_gap = 0;  ///< mean |falling − rising| over the 10–90 % levels (output unit)
  double major_gap_max = 0;
  double nested_gap_small = 0;  ///< reversals of ±5 % of the drive range
  double nested_gap_large = 0;  ///< reversals of ±20 %
  double mean_abs_error = 0;    ///< |truth − target| at the read points
};

/// The fixed protocol on the truth channel: targets at the static curve's 10..90 % levels up and
/// down with a fixed dwell; then nested reversals at 30/50/70 %.
GapResult BranchGap(FingerRig& rig, const std::vector<protocol::InversePoint>& inverse,
                    int dwell_ms);

struct TrackingResult {
  double rms = 0, max = 0;  ///< truth − target, output unit, over the whole record
  bool saturated = false;   ///< the board said saturated at some point
  bool finite = true;
};

enum class InputSet { kDemoStimuli, kBandLimitedRandom, kFastRamps };
const char* InputSetName(InputSet s);

/// Plays a held-out input set in target mode; `seconds` of it.
TrackingResult Track(FingerRig& rig, const std::vector<protocol::InversePoint>& inverse,
                     InputSet set, int seconds, uint32_t seed);

struct LevelResult {
  double mean_relative = 0, max_relative = 0;  ///< |truth − target| / target at settled levels
};

/// Random held-out levels over 10–90 % of the range, each held `dwell_ms`, read at its end.
LevelResult SettledLevels(FingerRig& rig, const std::vector<protocol::InversePoint>& inverse,
                          int levels, int dwell_ms, uint32_t seed);

/// The output the static inverse puts at a fraction of the drive range (its own table read back).
double OutputAtShare(const std::vector<protocol::InversePoint>& inverse, double share,
                     double drive_max);

}  // namespace palpa::testing
