// palpa-sim serving a board and the calibration rig on one of its fingers.
#include "sim_rig.h"

#include <cmath>
#include <cstdio>

#include "cli.h"
#include "palpa/host/transport.h"

namespace palpa::cli {

std::optional<SimRig> OpenSimRig(const std::string& config, int finger, double speed,
                                 const host::SimulatedPlant& plant, std::string* error) {
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
  auto transport = host::LaunchSim(config, sim_args, nullptr, error, &rig_address);
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

bool ParseSimPlantOption(const std::string& arg, const std::function<bool(std::string&)>& next,
                         host::SimulatedPlant& plant, std::string* error) {
  // palpa-sim's own ranges (palpa-sim --help), checked here so a bad value is a usage error.
  struct Integer {
    const char* name;
    double most;
    const char* expected;
  };
  static const Integer kIntegers[] = {{"--unit", 1000, "an actuator unit 0 to 1000"},
                                      {"--seed", 4294967295.0, "a seed 0 to 4294967295"},
                                      {"--plant", 3, "a plant level 0 to 3"}};
  std::string v;
  if (arg == "--effects") {
    if (!next(v)) v.clear();
    if (const std::string why = host::SimEffectsError(v); v.empty() || !why.empty()) {
      *error = "--effects " + v + ": " + (v.empty() ? "a list is missing" : why);
      return true;
    }
    plant.effects = v;
    return true;
  }
  for (const Integer& option : kIntegers) {
    if (arg != option.name) continue;
    double n = -1;
    if (!next(v) || !ParseNumber(v, n) || n < 0 || n > option.most || n != std::floor(n)) {
      *error = arg + " " + v + ": expected " + option.expected;
      return true;
    }
    if (arg == "--unit") plant.actuator_unit = static_cast<uint32_t>(n);
    if (arg == "--seed") plant.seed = static_cast<uint32_t>(n);
    if (arg == "--plant") plant.plant_level = static_cast<int>(n);
    return true;
  }
  return false;
}

std::string DescribeSimulatedPlant(const host::SimulatedPlant& plant) {
  return "simulated unit " + std::to_string(plant.actuator_unit) + ", seed " +
         std::to_string(plant.seed) + ", plant level " + std::to_string(plant.plant_level) +
         (plant.effects.empty() ? std::string() : ", effects " + plant.effects);
}

}  // namespace palpa::cli
