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

/// A rig file's text; a bad one is an invalid argument naming the field by its JSON path.
host::Result<RigDescription> ParseRigDescription(const std::string& text);
/// The file read (within kRigFileLimits) and parsed; errors start with "PATH: ".
host::Result<RigDescription> LoadRigDescription(const std::string& path);

struct RigDevices {
  std::unique_ptr<Stage> stage;
  std::unique_ptr<ForceSensor> force;
};

/// The description of palpa-sim's rig (calibration/rigs/sim.json) with both devices pointed at
/// `modbus_uri` (modbus-tcp://127.0.0.1:PORT/1, as palpa-sim printed it).
RigDescription SimRigDescription(const std::string& modbus_uri);

/// Connects both devices; on failure (unavailable, or not_found for an unknown host) nothing is
/// left open and the message says which device and why.
host::Result<RigDevices> OpenRigDevices(const RigDescription& rig);

}  // namespace palpa::calibration
