// Sensor and stage models of the plant's level 3.
#include "palpa/hal/sim/sensors.h"

#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;

PressureSensor::PressureSensor(float min_pa, float max_pa, bool ideal, uint32_t seed)
    : min_pa_(min_pa), max_pa_(max_pa), ideal_(ideal), rng_(seed) {
  if (!ideal_) {
    std::uniform_real_distribution<float> within(-1.0f, 1.0f);
    const float fss = max_pa_ - min_pa_;
    // Offset and gain share the accuracy budget (BFSL): each takes up to half of it.
    offset_pa_ = 0.5f * p::kPressureSensorAccuracyFss * fss * within(rng_);
    gain_ = 0.5f * p::kPressureSensorAccuracyFss * within(rng_);
  }
}

uint32_t PressureSensor::Read(float true_pa, float dt_s) {
  float pa = true_pa;
  const float fss = max_pa_ - min_pa_;
  if (!ideal_) {
    std::normal_distribution<float> noise(0.0f, p::kPressureSensorNoiseFssRms * fss);
    const float drift_rate = p::kPressureSensorDriftFssPerHour * fss / std::sqrt(3600.0f);
    std::normal_distribution<float> walk(0.0f, drift_rate * std::sqrt(std::max(dt_s, 0.0f)));
    drift_pa_ += walk(rng_);
    pa = true_pa * (1.0f + gain_) + offset_pa_ + drift_pa_ + noise(rng_);
  }
  const float span = p::kPressureSensorCountsMax - p::kPressureSensorCountsMin;
  const float counts = p::kPressureSensorCountsMin + (pa - min_pa_) / fss * span;
  const float top = static_cast<float>((1u << static_cast<int>(p::kPressureSensorBits)) - 1u);
  return static_cast<uint32_t>(std::clamp(std::round(counts), 0.0f, top));
}

float PressureSensor::PressureOf(uint32_t counts) const {
  const float span = p::kPressureSensorCountsMax - p::kPressureSensorCountsMin;
  return min_pa_ +
         (static_cast<float>(counts) - p::kPressureSensorCountsMin) / span * (max_pa_ - min_pa_);
}

ForceSensor::ForceSensor(bool ideal, uint32_t seed) : ideal_(ideal), rng_(seed) {}

float ForceSensor::Read(float true_n) {
  float f = true_n - tare_;
  if (!ideal_) {
    std::normal_distribution<float> noise(0.0f, p::kRigForceNoiseNRms);
    f += noise(rng_);
  }
  return std::round(f / p::kRigForceResolutionN) * p::kRigForceResolutionN;
}

void LinearStage::Step(float dt_s) {
  const float step = speed_mm_s_ * dt_s;
  const float error = target_mm_ - position_mm_;
  position_mm_ = std::fabs(error) <= step ? target_mm_ : position_mm_ + (error > 0 ? step : -step);
}

float LinearStage::encoder_mm() const {
  return std::round(position_mm_ / p::kRigStageResolutionMm) * p::kRigStageResolutionMm;
}

}  // namespace palpa::sim
