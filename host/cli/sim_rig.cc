// palpa-sim serving a board and the calibration rig on one of its fingers.
#include "sim_rig.h"

#include <cstdio>

#include "palpa/host/transport.h"

namespace palpa::cli {

std::optional<SimRig> OpenSimRig(const std::string& config, int finger, double speed,
                                 std::string* error) {
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::string rig_address;
  auto transport = host::LaunchSim(config,
                                   {"--speed", speed_text, "--rig-modbus", "tcp:127.0.0.1:0",
                                    "--rig-finger", std::to_string(finger)},
                                   nullptr, error, &rig_address);
  if (!transport.ok()) return std::nullopt;
  host::DeviceOptions options;
  options.number_from = 1;  // as the command line numbers fingers
  auto device = host::Device::Attach(std::move(transport.value), options, error);
  if (!device.ok()) return std::nullopt;
  SimRig sim;
  sim.device = std::move(device.value);
  sim.description = calibration::SimRigDescription("modbus-tcp://" + rig_address.substr(4) + "/1");
  auto devices = calibration::OpenRigDevices(sim.description, error);
  if (!devices) {
    *error = "rig " + sim.description.name + ": " + *error;
    return std::nullopt;
  }
  sim.devices = std::move(*devices);
  return sim;
}

}  // namespace palpa::cli
