// palpa-sim serving a board and the calibration rig on one of its fingers (`--rig sim`).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "palpa/calibration/device_rig.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/host/device.h"

namespace palpa::cli {

/// A simulator of its own: the board it runs (`config`, default plant and units, so a finger's
/// actuator is the one every other simulator of that configuration has) and its rig's devices.
struct SimRig {
  std::unique_ptr<host::Device> device;
  calibration::RigDescription description;
  calibration::RigDevices devices;
};

/// Starts palpa-sim at `speed` with its rig on `finger` (from 0). Empty with *error when it
/// cannot.
std::optional<SimRig> OpenSimRig(const std::string& config, int finger, double speed,
                                 std::string* error);

}  // namespace palpa::cli
