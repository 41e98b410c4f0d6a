// The MPS2 board has no DAC or sensors: the image links the level-1 plant (regulators and
// chambers, freestanding) behind the analogue interfaces, and Hello says the plant is simulated.
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/sim/plant_params.h"
#include "palpa/hal/sim/regulator_line.h"

namespace palpa::boards::mps2 {

namespace params = palpa::sim::params;

/// The converters as a board with real ones has them: DAC codes land in registers that the
/// regulators follow, and the ADC's scan leaves its results in a buffer (as DMA would) that the
/// tick copies. The conversions themselves (code → regulator command, pressure → counts) are the
/// plant's side and run in its millisecond step, outside the control tick.
class PlantIo final : public hal::AnalogOutput, public hal::AnalogInput {
 public:
  /// Regulators wired as the configuration says (no static errors: an ideal unit).
  void Init(const core::BoardConfig& config) {
    count_ = config.line_count;
    for (uint8_t i = 0; i < count_; ++i) {
      config_[i] = config.lines[i];
      const sim::RegulatorSetup s = sim::NominalRegulatorSetup(config.lines[i].kind);
      lines_[i] = sim::RegulatorLine(s, 0.001f);
      codes_[i] = 0;
      scan_[i] = SensorCounts(i);
    }
  }
  /// One millisecond of plant time; `vented` while the board holds no valves, `line_vents` the
  /// lines whose own dump valves the board opened (bit i: line i). The regulators
  /// follow the codes in the DAC's registers; the scan buffer then holds what the sensors read.
  void Step(bool vented, uint32_t line_vents) {
    for (uint8_t i = 0; i < count_; ++i)
      lines_[i].Step(RegulatorCommand(i), vented, (line_vents >> i & 1u) != 0);
    for (uint8_t i = 0; i < count_; ++i) scan_[i] = SensorCounts(i);
  }
  float chamber_pa(uint8_t line) const { return lines_[line].chamber_pa(); }

 private:
  protocol::Status DoWrite(uint8_t channel, uint32_t counts) override {
    if (channel >= count_) return protocol::Status::kNotFound;
    codes_[channel] = counts;
    return protocol::Status::kOk;
  }
  uint8_t DoWriteAll(const uint32_t* codes, uint8_t count) override {
    const uint8_t n = count < count_ ? count : count_;
    for (uint8_t i = 0; i < n; ++i) codes_[i] = codes[i];
    return count <= count_ ? kAllWritten : count_;
  }
  hal::AnalogOutputSpec DoSpec(uint8_t) const override { return {}; }
  protocol::Result<uint32_t> DoRead(uint8_t channel) override {
    if (channel >= count_) return protocol::Status::kNotFound;
    return scan_[channel];
  }
  void DoReadAll(uint32_t* counts, uint8_t count) override {
    const uint8_t n = count < count_ ? count : count_;
    for (uint8_t i = 0; i < n; ++i) counts[i] = scan_[i];
    for (uint8_t i = n; i < count; ++i) counts[i] = kConversionFailed;
  }
  uint8_t DoBits() const override { return 14; }

  /// What the regulator on `channel` is told by the code in its DAC register.
  float RegulatorCommand(uint8_t channel) const {
    const protocol::ConfigureLine& c = config_[channel];
    const float fraction =
        static_cast<float>(codes_[channel]) / static_cast<float>((1u << c.dac_bits) - 1u);
    return (c.kind == protocol::LineKind::kVacuum ? -1.0f : 1.0f) * fraction *
           params::kRegulatorFullScalePa;
  }
  /// What the ADC converts the sensor on `channel` to.
  uint32_t SensorCounts(uint8_t channel) const {
    const protocol::ConfigureLine& c = config_[channel];
    const float pa = lines_[channel].outlet_pa();
    const float fraction = (pa - static_cast<float>(c.sensor_min_pa)) /
                           static_cast<float>(c.sensor_max_pa - c.sensor_min_pa);
    const float counts = static_cast<float>(c.sensor_counts_min) +
                         fraction * static_cast<float>(c.sensor_counts_max - c.sensor_counts_min);
    return static_cast<uint32_t>(counts < 0 ? 0.0f : counts + 0.5f);
  }

  uint8_t count_ = 0;
  protocol::ConfigureLine config_[protocol::kMaxLines] = {};
  sim::RegulatorLine lines_[protocol::kMaxLines];
  uint32_t codes_[protocol::kMaxLines] = {};  ///< the DAC's registers
  uint32_t scan_[protocol::kMaxLines] = {};   ///< the ADC's last scan
};

}  // namespace palpa::boards::mps2
