// A rig described by a JSON file: its stage and force sensor (driver, address, register map)
// and its safety limits. Parsing names the field that is wrong; opening connects the devices.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "palpa/calibration/netft.h"
#include "palpa/calibration/register_map.h"
#include "palpa/calibration/rig.h"
#include "palpa/host/file_read.h"

namespace palpa::calibration {

struct RigDescription {
  std::string name;
  RegisterMap stage;
  RegisterMap force;                 ///< a Modbus force sensor...
  std::optional<NetFtConfig> netft;  ///< ...or an ATI Net F/T
  SafetyLimits limits;
  double force_noise_n = kNano17NoiseN;  ///< the force sensor's class: RMS noise of one reading
};

/// A rig file is a few KiB.
inline constexpr host::FileLimits kRigFileLimits{"rig file", 64 * 1024};

std::optional<RigDescription> ParseRigDescription(const std::string& text, std::string* error);
std::optional<RigDescription> LoadRigDescription(const std::string& path, std::string* error);

struct RigDevices {
  std::unique_ptr<Stage> stage;
  std::unique_ptr<ForceSensor> force;
};

/// The description of palpa-sim's rig (calibration/rigs/sim.json) with both devices pointed at
/// `modbus_uri` (modbus-tcp://127.0.0.1:PORT/1, as palpa-sim printed it).
RigDescription SimRigDescription(const std::string& modbus_uri);

/// Connects both devices; on failure nothing is left open and *error says which device and why.
std::optional<RigDevices> OpenRigDevices(const RigDescription& rig, std::string* error);

}  // namespace palpa::calibration
