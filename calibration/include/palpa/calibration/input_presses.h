// Pen pressure calibration: a few presses of the pen on the rig's force sensor, each held still
// until both the pen's level and the sensor's force are steady, paired as (level, force) for the
// exponential fit (scene_tablet.h FitPressureForce).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "palpa/calibration/rig.h"
#include "palpa/host/scene_tablet.h"

namespace palpa::calibration {

/// The pen as the procedure needs it: whether it touches, and its level (0 … 1 023).
struct PenState {
  bool touching = false;
  double level = 0;
};
class PenLevels {
 public:
  virtual ~PenLevels() = default;
  /// The pen's state after its next report, or nothing when none came within `timeout_ms` (the
  /// state is then unchanged). A pen that went away is an error.
  virtual host::Result<std::optional<PenState>> Next(int timeout_ms) = 0;
};

struct PressOptions {
  size_t presses = 5;
  double steady_s = 0.5;                ///< held this long within the tolerances below
  double level_tolerance = 6;           ///< levels, peak to peak over steady_s
  double force_tolerance_n = 0.03;      ///< peak to peak over steady_s, plus …
  double force_tolerance_share = 0.03;  ///< … this share of the force (a hand's tremor scales)
  double min_force_n = 0.02;            ///< a press lighter than this is not on the sensor
  double distinct_levels = 60;  ///< presses closer than this in level add nothing to the fit
  double timeout_s = 120;       ///< for the whole run
};

/// Tares the sensor with the pen lifted, then collects `presses` steady presses at levels at
/// least `distinct_levels` apart, telling the person what to do through `say`. Unavailable when
/// the time runs out (saying how many presses were taken), the sensor's or the pen's error as it
/// came.
host::Result<std::vector<host::Press>> CollectPresses(
    PenLevels& pen, ForceSensor& sensor, RigTime& time, const PressOptions& options,
    const std::function<void(const std::string&)>& say);

}  // namespace palpa::calibration
