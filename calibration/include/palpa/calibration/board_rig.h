// A finger's calibration rig on its board: palpa-sim serving a board and the rig on one of its
// fingers (`--rig sim`), or a rig file's stage and force sensor beside a board the caller opened.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "palpa/calibration/device_rig.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"

namespace palpa::calibration {

struct BoardRig {
  /// palpa-sim's board, which this rig started (empty for a rig file's: the caller's board).
  std::unique_ptr<host::Device> own_device;
  host::Device* device = nullptr;
  RigDescription description;
  RigDevices devices;
  std::unique_ptr<DeviceBoardPort> board;
  std::unique_ptr<BoardTime> time;
  /// palpa-sim's own account of the plant it runs (its unit, seed and level as it announced them;
  /// the effects asked for): what a calibration on it records and says.
  host::SimulatedPlant simulation;

  bool simulated() const { return own_device != nullptr; }
  /// The rig as procedures and sessions take it.
  Rig rig() {
    return Rig{*devices.stage,   *devices.force,           *board, *time, description.limits,
               description.name, description.force_noise_n};
  }
};

/// Starts palpa-sim of `config` at `speed` with `plant` (its unit, seed, level and effects, so a
/// finger's actuator is the one every other simulator of that configuration and unit has) and
/// its rig on `finger` (from 0); the board numbers fingers from `number_from`. kUnavailable, and
/// why, when it cannot, or when palpa-sim does not announce the plant asked for.
host::Result<BoardRig> OpenSimulatedRig(const std::string& config, int finger, double speed,
                                        const host::SimulatedPlant& plant, int number_from);

/// The stage and force sensor `description` names, beside `device`. kUnavailable ("rig NAME:
/// ...") when one cannot be opened.
host::Result<BoardRig> OpenBoardRig(host::Device& device, const RigDescription& description);

/// The actuator serial finger `finger` carries: kInvalidArgument when the board has no such
/// finger, kBadValue (the message quoting the serial as read) when it is not usable for a
/// calibration's name.
host::Result<std::string> ReadActuatorSerial(host::Device& device, uint8_t finger);

}  // namespace palpa::calibration
