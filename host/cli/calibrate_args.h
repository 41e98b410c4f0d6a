// palpa calibrate's command line: what it asks for, parsed and checked before anything starts.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/calibration_file.h"
#include "palpa/protocol/enums.h"

namespace palpa::cli {

struct CalibrateArgs {
  std::string rig;
  int finger = -1;
  std::string protocol = "thesis";
  std::string out;
  bool resume = false;
  bool quick = false;
  bool apply = false;
  double speed = 4;
  double target_pct = 2.5;
  int max_cycles = 18;
  std::optional<protocol::CompensatorKind> compensator;  ///< empty: the better of pi and api
  int operators = 0;     ///< 0: the protocol's default (16, or 8 with --quick)
  std::string previous;  ///< empty: DIR/SERIAL.json when there is one
  /// A compensator that cannot be fitted leaves the static inverse alone instead of failing.
  bool allow_fallback = false;
  host::SimulatedPlant plant;  ///< --rig sim: the simulator's unit, seed, level and effects
  bool plant_options = false;  ///< one of them was given
};

/// The command line into `a`; a usage error's exit code when it is malformed, else kExitOk.
int ParseCalibrateArgs(const std::vector<std::string>& args, CalibrateArgs& a);
/// What the arguments say together, and the output directory, checked before anything starts:
/// a refused command leaves nothing (the directory is made only once everything is checked).
int CheckCalibrateArgs(const CalibrateArgs& a);

}  // namespace palpa::cli
