// palpa-sim serving a board and the calibration rig on one of its fingers (`--rig sim`), and the
// simulator's options a calibration takes for it.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "palpa/calibration/device_rig.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"

namespace palpa::cli {

/// A simulator of its own: the board it runs (`config`, and the plant's unit, seed, level and
/// effects, so a finger's actuator is the one every other simulator of that configuration and
/// unit has) and its rig's devices.
struct SimRig {
  std::unique_ptr<host::Device> device;
  calibration::RigDescription description;
  calibration::RigDevices devices;
};

/// Starts palpa-sim at `speed` with `plant` and its rig on `finger` (from 0). Empty with *error
/// when it cannot.
std::optional<SimRig> OpenSimRig(const std::string& config, int finger, double speed,
                                 const host::SimulatedPlant& plant, std::string* error);

/// One of the simulator's options on a command line (--unit N, --seed N, --plant LEVEL,
/// --effects LIST) into `plant`: true when `arg` is one, with *error set when its value is bad
/// (naming it and what was expected); `next` gives the value.
bool ParseSimPlantOption(const std::string& arg, const std::function<bool(std::string&)>& next,
                         host::SimulatedPlant& plant, std::string* error);

/// "simulated unit 2, seed 1, plant level 3, effects creep" (no effects: none named).
std::string DescribeSimulatedPlant(const host::SimulatedPlant& plant);

}  // namespace palpa::cli
