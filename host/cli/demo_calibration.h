// The demo's calibration step: each pneumatic finger of a simulated board calibrated on a
// simulated rig of its own, all at once, as `palpa calibrate --rig sim --quick` would.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"

namespace palpa::cli {

/// The compensator the demo fits: api with 8 operators (docs/hysteresis.md: the asymmetric model
/// follows the film's low-pressure end, where pi leaves tens of micrometres).
inline constexpr int kDemoOperators = 8;

/// The board's pneumatic fingers (from 0) and their actuators' serials.
struct PneumaticFingers {
  std::vector<int> fingers;
  std::vector<std::string> serials;
};

PneumaticFingers FindPneumatic(host::Device& d);

/// The calibration files of --calibration DIR (DIR/SERIAL.json), read before anything runs;
/// empty (printed) when DIR has none of these fingers' or one cannot be read.
std::optional<std::vector<host::CalibrationFile>> ReadCalibrationDir(const PneumaticFingers& p,
                                                                     const std::string& dir);

/// Calibrates the pneumatic fingers of `config` on simulated rigs of their own, all at once (the
/// quick protocol, api(8)); each file keeps its detectors' flags. Empty (printed) on failure.
std::optional<std::vector<host::CalibrationFile>> CalibrateOnSimulatedRigs(
    const std::string& config, const PneumaticFingers& p, double speed);

/// Uploads each file to the finger carrying its actuator and prints its fit; `compensator` says
/// what was applied ("calibrated, api(8)"). False (printed) when the board refuses one.
bool ApplyCalibrations(host::Device& d, const PneumaticFingers& p,
                       const std::vector<host::CalibrationFile>& files, std::string* compensator);

}  // namespace palpa::cli
