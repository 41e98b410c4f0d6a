// A finger's calibration rig on its board: palpa-sim's, or a rig file's devices.
#include "palpa/calibration/board_rig.h"

#include <cstdio>
#include <vector>

#include "palpa/calibration/session.h"
#include "palpa/host/field_text.h"
#include "palpa/host/transport.h"

namespace palpa::calibration {

std::optional<BoardRig> OpenSimulatedRig(const std::string& config, int finger, double speed,
                                         const host::SimulatedPlant& plant, int number_from,
                                         std::string* error) {
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::vector<std::string> sim_args = {"--speed",      speed_text,
                                       "--rig-modbus", "tcp:127.0.0.1:0",
                                       "--rig-finger", std::to_string(finger),
                                       "--unit",       std::to_string(plant.actuator_unit),
                                       "--seed",       std::to_string(plant.seed),
                                       "--plant",      std::to_string(plant.plant_level)};
  if (!plant.effects.empty()) sim_args.insert(sim_args.end(), {"--effects", plant.effects});
  std::string rig_address;
  auto transport = host::LaunchSim(config, sim_args, nullptr, &rig_address);
  if (!transport.ok()) {
    *error = transport.message;
    return std::nullopt;
  }
  host::DeviceOptions options;
  options.number_from = static_cast<uint8_t>(number_from);
  auto device = host::Device::Attach(std::move(transport.value), options);
  if (!device.ok()) {
    *error = device.message;
    return std::nullopt;
  }
  auto rig = OpenBoardRig(*device.value,
                          SimRigDescription("modbus-tcp://" + rig_address.substr(4) + "/1"), error);
  if (!rig) return std::nullopt;
  rig->own_device = std::move(device.value);
  return rig;
}

std::optional<BoardRig> OpenBoardRig(host::Device& device, const RigDescription& description,
                                     std::string* error) {
  auto devices = OpenRigDevices(description, error);
  if (!devices) {
    *error = "rig " + description.name + ": " + *error;
    return std::nullopt;
  }
  BoardRig rig;
  rig.device = &device;
  rig.description = description;
  rig.devices = std::move(*devices);
  rig.board = std::make_unique<DeviceBoardPort>(device);
  rig.time = std::make_unique<BoardTime>(device);
  return rig;
}

host::Outcome ReadActuatorSerial(host::Device& device, uint8_t finger, std::string* serial) {
  if (finger >= device.info().finger_count) {
    return host::Outcome{protocol::Status::kInvalidArgument,
                         "the board has " + std::to_string(device.info().finger_count) + " fingers",
                         {}};
  }
  const auto config = device.ReadFinger(finger);
  if (!config.ok()) return host::Outcome{config.status, config.message, {}};
  *serial = host::FieldText(config.value.actuator_serial);
  if (!host::ValidSerial(*serial)) {
    return host::Outcome{
        protocol::Status::kBadValue,
        device.FingerName(finger) + " has no usable actuator serial ('" + *serial + "')",
        {}};
  }
  return {};
}

}  // namespace palpa::calibration
