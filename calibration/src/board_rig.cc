// A finger's calibration rig on its board: palpa-sim's, or a rig file's devices.
#include "palpa/calibration/board_rig.h"

#include <cstdio>
#include <vector>

#include "palpa/calibration/session.h"
#include "palpa/host/field_text.h"
#include "palpa/host/transport.h"

namespace palpa::calibration {

host::Result<BoardRig> OpenSimulatedRig(const std::string& config, int finger, double speed,
                                        const host::SimulatedPlant& plant, int number_from) {
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::vector<std::string> sim_args = {"--speed",      speed_text,
                                       "--rig-modbus", "tcp:127.0.0.1:0",
                                       "--rig-finger", std::to_string(finger),
                                       "--unit",       std::to_string(plant.actuator_unit),
                                       "--seed",       std::to_string(plant.seed),
                                       "--plant",      std::to_string(plant.plant_level)};
  if (!plant.effects.empty()) sim_args.insert(sim_args.end(), {"--effects", plant.effects});
  std::string rig_address, announcement;
  auto transport = host::LaunchSim(config, sim_args, nullptr, &rig_address, &announcement);
  if (!transport.ok()) return {Status::kUnavailable, transport.message};
  // What the simulator says it runs, not what was asked of it, is what the calibration records.
  host::SimulatedPlant running;
  running.effects = plant.effects;
  if (std::sscanf(announcement.c_str(), "palpa-sim: %*[^,], plant level %d, unit %u, seed %u",
                  &running.plant_level, &running.actuator_unit, &running.seed) != 3) {
    return {Status::kUnavailable, "palpa-sim did not say which plant it runs: " + announcement};
  }
  if (running.actuator_unit != plant.actuator_unit || running.seed != plant.seed ||
      running.plant_level != plant.plant_level) {
    return {Status::kUnavailable,
            "palpa-sim runs another plant than the one asked for: " + announcement};
  }
  host::DeviceOptions options;
  options.number_from = static_cast<uint8_t>(number_from);
  auto device = host::Device::Attach(std::move(transport.value), options);
  if (!device.ok()) return {Status::kUnavailable, device.message};
  auto rig = OpenBoardRig(*device.value,
                          SimRigDescription("modbus-tcp://" + rig_address.substr(4) + "/1"));
  if (rig.ok()) {
    rig.value.own_device = std::move(device.value);
    rig.value.simulation = running;
  }
  return rig;
}

host::Result<BoardRig> OpenBoardRig(host::Device& device, const RigDescription& description) {
  auto devices = OpenRigDevices(description);
  if (!devices.ok())
    return {Status::kUnavailable, "rig " + description.name + ": " + devices.message};
  BoardRig rig;
  rig.device = &device;
  rig.description = description;
  rig.devices = std::move(devices.value);
  rig.board = std::make_unique<DeviceBoardPort>(device);
  rig.time = std::make_unique<BoardTime>(device);
  return rig;
}

host::Result<std::string> ReadActuatorSerial(host::Device& device, uint8_t finger) {
  if (finger >= device.info().finger_count) {
    return {Status::kInvalidArgument,
            "the board has " + std::to_string(device.info().finger_count) + " fingers"};
  }
  const auto config = device.ReadFinger(finger);
  if (!config.ok()) return config.outcome();
  std::string serial = host::FieldText(config.value.actuator_serial);
  if (!host::ValidSerial(serial)) {
    return {Status::kBadValue,
            device.FingerName(finger) + " has no usable actuator serial ('" + serial + "')"};
  }
  return serial;
}

}  // namespace palpa::calibration
