// Plant composition: DAC code → regulator → chamber → actuator; sensors read the outlet.
#include "palpa/hal/sim/plant.h"

#include <random>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;
namespace {

/// A regulator unit's static errors: each within its specification, never negligibly small, so
/// that feed-forward alone shows the regulator's error as the thesis hardware would.
RegulatorErrors DrawErrors(std::mt19937& rng) {
  std::uniform_real_distribution<float> size(0.5f, 1.0f);
  std::bernoulli_distribution positive(0.5);
  auto draw = [&](float spec) { return spec * size(rng) * (positive(rng) ? 1.0f : -1.0f); };
  const float fs = p::kRegulatorFullScalePa;
  RegulatorErrors e;
  e.gain = draw(p::kRegulatorGainError);
  e.offset_pa = draw(p::kRegulatorOffsetFs * fs);
  e.linearity_pa = draw(p::kRegulatorLinearityFs * fs);
  // Hysteresis (full loop width) plus sensitivity (dead band) act as one backlash.
  e.play_pa = 0.5f * (p::kRegulatorHysteresisFs + p::kRegulatorSensitivityFs) * fs;
  return e;
}

}  // namespace

Plant::Plant(const protocol::ConfigureLine* lines, uint8_t line_count,
             const protocol::ConfigureFinger* fingers, uint8_t finger_count, PlantOptions options)
    : options_(options) {
  std::mt19937 rng(options.seed * 2654435761u + 17u);
  for (uint8_t i = 0; i < line_count; ++i) {
    Line line;
    line.config = lines[i];
    RegulatorSetup setup = NominalRegulatorSetup(lines[i].kind, options.flow);
    setup.dead_time_s *= options.dead_time_scale;
    if (options.level < 1) setup.min_set_pa = 0.0f;
    setup.dynamics = options.level >= 1;
    const RegulatorErrors drawn = DrawErrors(rng);
    if (options.level >= 1 && options.static_errors) setup.errors = drawn;
    line.regulator = RegulatorLine(setup, kStepS);
    line.sensor = std::make_unique<PressureSensor>(static_cast<float>(lines[i].sensor_min_pa),
                                                   static_cast<float>(lines[i].sensor_max_pa),
                                                   options.level < 3, static_cast<uint32_t>(rng()));
    line.counts = line.sensor->Read(0, 0);
    lines_.push_back(std::move(line));
  }
  // Actuator units: unit 0 is the nominal actuator; others differ by the assumed unit spread — a
  // jamming chamber by its size (a gain, §5.4.1), a pneumatic film in gain, growth and width.
  // The shape comes from a stream of its own, so each unit's gains are what they always were.
  std::mt19937 unit_rng(options.unit * 7919u + 3u);
  std::mt19937 shape_rng(options.unit * 104729u + 11u);
  const float unit_spread = p::kPneumaticUnitSpread * options.effects.unit_spread;
  std::normal_distribution<float> spread(1.0f, unit_spread);
  std::normal_distribution<float> growth(0.0f, p::kPneumaticUnitGrowthShare * unit_spread);
  std::normal_distribution<float> width(1.0f, p::kPneumaticUnitWidthShare * unit_spread);
  for (uint8_t f = 0; f < finger_count; ++f) {
    Finger finger;
    finger.config = fingers[f];
    const bool nominal = options.unit == 0;
    const float gain = nominal ? 1.0f : spread(unit_rng);
    PneumaticUnit pneumatic;
    if (!nominal) {
      // The same draw, scaled to the part of the spread that is a plain gain.
      pneumatic.gain = 1.0f + (gain - 1.0f) * p::kPneumaticUnitGainShare;
      pneumatic.growth = growth(shape_rng);
      pneumatic.width = width(shape_rng);
    }
    const Effects effects = options.level >= 2 ? options.effects : Effects{};
    if (fingers[f].kind == protocol::FingerKind::kJamming) {
      finger.jamming = std::make_unique<JammingActuator>(gain, effects);
      finger.jamming->Reset();
    } else {
      finger.pneumatic = std::make_unique<PneumaticActuator>(pneumatic, effects);
    }
    fingers_.push_back(std::move(finger));
  }
}

float Plant::NominalCommand(const protocol::ConfigureLine& c, uint32_t counts) const {
  const float max = static_cast<float>((1u << c.dac_bits) - 1u);
  float fraction = static_cast<float>(counts) / max;
  if (c.dac_signal == protocol::SignalRange::kMilliamp4To20) fraction = (fraction - 0.2f) / 0.8f;
  const float sign = c.kind == protocol::LineKind::kVacuum ? -1.0f : 1.0f;
  return sign * (fraction < 0 ? 0.0f : fraction) * p::kRegulatorFullScalePa;
}

void Plant::SetDacCounts(uint8_t line, uint32_t counts) {
  if (line >= lines_.size()) return;
  lines_[line].command_pa = NominalCommand(lines_[line].config, counts);
}

uint32_t Plant::SensorCounts(uint8_t line) const {
  return line < lines_.size() ? lines_[line].counts : 0;
}

JammingActuator* Plant::jamming(uint8_t finger) {
  return finger < fingers_.size() ? fingers_[finger].jamming.get() : nullptr;
}

PneumaticActuator* Plant::pneumatic(uint8_t finger) {
  return finger < fingers_.size() ? fingers_[finger].pneumatic.get() : nullptr;
}

void Plant::Step() {
  time_s_ += kStepS;
  for (size_t i = 0; i < lines_.size(); ++i) {
    Line& line = lines_[i];
    line.regulator.Step(line.command_pa, vented_, (line_vents_ >> i & 1u) != 0);
    line.counts = line.sensor->Read(line.regulator.outlet_pa(), kStepS);
  }
  for (Finger& f : fingers_) {
    const float a = lines_[f.config.line_a].regulator.chamber_pa();
    if (f.jamming) {
      const float b =
          f.config.line_b < lines_.size() ? lines_[f.config.line_b].regulator.chamber_pa() : 0.0f;
      f.jamming->Step(a, b);
    } else if (f.pneumatic) {
      f.pneumatic->Step(a, kStepS);
    }
  }
}

PlantTruth Plant::Truth() const {
  PlantTruth t;
  t.time_s = time_s_;
  for (const Line& line : lines_) {
    t.lines.push_back(
        LineTruth{line.command_pa, line.regulator.outlet_pa(), line.regulator.chamber_pa()});
  }
  for (const Finger& f : fingers_) {
    FingerTruth ft;
    ft.jamming = f.jamming != nullptr;
    if (f.jamming) {
      ft.stiffness_n_per_mm =
          options_.level >= 2
              ? f.jamming->stiffness()
              : f.jamming->StaticStiffness(lines_[f.config.line_a].regulator.chamber_pa(),
                                           lines_[f.config.line_b].regulator.chamber_pa());
    } else if (f.pneumatic) {
      const float kpa = lines_[f.config.line_a].regulator.chamber_pa() / 1000.0f;
      // Below level 2 the film has no memory: the middle of its major loop.
      ft.deformation_mm =
          options_.level >= 2
              ? f.pneumatic->deformation_mm()
              : 0.5f * (f.pneumatic->RisingMajorMm(kpa) + f.pneumatic->FallingMajorMm(kpa));
    }
    t.fingers.push_back(ft);
  }
  return t;
}

}  // namespace palpa::sim
