// Whether a board configuration's lines can sit on the analogue I/O module (docs/linux.md).
#include "board_file.h"
#include "palpa/core/board.h"
#include "palpa/core/line_pipeline.h"

namespace palpa::linux_board {

uint32_t SafeValueCode(const protocol::ConfigureLine& line) {
  return core::MakeLineParams(line, core::Board::kTickUs).safe_counts;
}

const char* SafeValueNotAtZeroVolts(const protocol::ConfigureLine& line) {
  // The module's fallback is 0 V on every output when the controller dies: a line is safe then
  // only if its safe value is what 0 V commands.
  if (SafeValueCode(line) == 0) return nullptr;
  return "safe value not commanded by 0 V: the module's fallback (0 V on every output) would not "
         "make the line safe";
}

hal::Done FitsTheModule(const core::BoardConfig& config, const std::string& name,
                        const hal::linux_aio::ModbusAioConfig& module) {
  const auto refused = [](std::string why) {
    return hal::Done(hal::Status::kBadValue, std::move(why));
  };
  // The core writes channels 0..lines-1 in one transfer: a channel the module lacks would fail
  // every write, and the board would only ever latch output_write.
  if (config.line_count > module.output_count) {
    return refused("board: " + name + " has " + std::to_string(config.line_count) +
                   " lines, but analog_module.outputs.count is " +
                   std::to_string(module.output_count));
  }
  for (uint8_t i = 0; i < config.line_count; ++i) {
    const protocol::ConfigureLine& line = config.lines[i];
    const std::string which = "board: " + name + " line " + std::to_string(i);
    if (line.dac_signal != protocol::SignalRange::kVolt0To10) {
      return refused(which + ": its command signal is " +
                     protocol::EnumNames(line.dac_signal)[static_cast<unsigned>(line.dac_signal)] +
                     ", the module's outputs are 0-10V");
    }
    if (line.dac_bits != module.output_bits) {
      return refused(which + ": a " + std::to_string(line.dac_bits) +
                     "-bit command, but analog_module.outputs.bits is " +
                     std::to_string(module.output_bits));
    }
    if (line.sensor != protocol::SensorKind::kNone) {
      if (i >= module.input_count) {
        return refused(which + ": its sensor needs input " + std::to_string(i) +
                       ", but analog_module.inputs.count is " + std::to_string(module.input_count));
      }
      if (line.adc_bits != module.input_bits) {
        return refused(which + ": a " + std::to_string(line.adc_bits) +
                       "-bit sensor, but analog_module.inputs.bits is " +
                       std::to_string(module.input_bits));
      }
    }
    // The rule a host's change meets too (the board's line check), and what it found here.
    if (const char* why = SafeValueNotAtZeroVolts(line)) {
      return refused(which + ": " + why + " (its safe value, " + std::to_string(line.safe_pa) +
                     " Pa, is code " + std::to_string(SafeValueCode(line)) + ")");
    }
  }
  return {};
}

}  // namespace palpa::linux_board
