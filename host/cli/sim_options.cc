// The simulator's options on palpa calibrate's command line.
#include "sim_options.h"

#include <cmath>

#include "cli.h"

namespace palpa::cli {

host::Result<bool> ParseSimPlantOption(const std::string& arg,
                                       const std::function<bool(std::string&)>& next,
                                       host::SimulatedPlant& plant) {
  using protocol::Status;
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
      return {Status::kInvalidArgument,
              "--effects " + v + ": " + (v.empty() ? "a list is missing" : why)};
    }
    plant.effects = v;
    return true;
  }
  for (const Integer& option : kIntegers) {
    if (arg != option.name) continue;
    double n = -1;
    if (!next(v) || !ParseNumber(v, n) || n < 0 || n > option.most || n != std::floor(n)) {
      return {Status::kInvalidArgument, arg + " " + v + ": expected " + option.expected};
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
