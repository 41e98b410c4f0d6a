// The simulator's options a calibration takes for `--rig sim` (--unit, --seed, --plant,
// --effects), and how the command line names them.
#pragma once

#include <functional>
#include <string>

#include "palpa/host/calibration_file.h"

namespace palpa::cli {

/// One of the simulator's options on a command line (--unit N, --seed N, --plant LEVEL,
/// --effects LIST) into `plant`: true when `arg` is one, false when it is not; an invalid argument
/// when its value is bad (naming it and what was expected). `next` gives the value.
host::Result<bool> ParseSimPlantOption(const std::string& arg,
                                       const std::function<bool(std::string&)>& next,
                                       host::SimulatedPlant& plant);

/// "simulated unit 2, seed 1, plant level 3, effects creep" (no effects: none named).
std::string DescribeSimulatedPlant(const host::SimulatedPlant& plant);

}  // namespace palpa::cli
