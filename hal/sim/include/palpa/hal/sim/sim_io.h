// hal backends over the simulated plant: the board's DAC feeds the regulators, its ADC reads
// the pressure sensors.
#pragma once

#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/sim/plant.h"

namespace palpa::sim {

class SimAnalogOutput final : public hal::AnalogOutput {
 public:
  explicit SimAnalogOutput(Plant& plant) : plant_(plant) {}

 private:
  protocol::Status DoWrite(uint8_t channel, uint32_t counts) override {
    if (channel >= plant_.line_count()) return protocol::Status::kNotFound;
    plant_.SetDacCounts(channel, counts);
    return protocol::Status::kOk;
  }
  hal::AnalogOutputSpec DoSpec(uint8_t) const override { return {}; }
  Plant& plant_;
};

class SimAnalogInput final : public hal::AnalogInput {
 public:
  explicit SimAnalogInput(const Plant& plant) : plant_(plant) {}

 private:
  protocol::Result<uint32_t> DoRead(uint8_t channel) override {
    if (channel >= plant_.line_count()) return protocol::Status::kNotFound;
    return plant_.SensorCounts(channel);
  }
  uint8_t DoBits() const override { return 14; }
  const Plant& plant_;
};

}  // namespace palpa::sim
