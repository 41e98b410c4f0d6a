// Level 3 of the plant: the pressure sensor (HSC class), the force sensor (Nano17 class) and the
// rig's linear stage. Host only.
#pragma once

#include <cstdint>
#include <random>

namespace palpa::sim {

/// Pressure sensor with a 14-bit output over 10-90 % of counts. An ideal sensor only quantises;
/// a real one adds its unit's offset and gain error (within ±0.25 % FSS), noise and drift.
class PressureSensor {
 public:
  PressureSensor(float min_pa, float max_pa, bool ideal, uint32_t seed);
  /// Counts for the true pressure at the sensor; dt advances the drift.
  uint32_t Read(float true_pa, float dt_s);
  /// The pressure a set of counts stands for (the inverse transfer function, no errors).
  float PressureOf(uint32_t counts) const;

 private:
  float min_pa_, max_pa_;
  bool ideal_;
  std::mt19937 rng_;
  float offset_pa_ = 0, gain_ = 0, drift_pa_ = 0;
};

/// Force sensor: Gaussian noise, then quantised to its resolution (0.003 N).
class ForceSensor {
 public:
  ForceSensor(bool ideal, uint32_t seed);
  float Read(float true_n);
  float tare() const { return tare_; }
  void Tare(float true_n) { tare_ = true_n; }

 private:
  bool ideal_;
  std::mt19937 rng_;
  float tare_ = 0;
};

/// Linear stage: moves toward a target at a set speed, reports an encoder position.
class LinearStage {
 public:
  void MoveTo(float target_mm, float speed_mm_s) {
    target_mm_ = target_mm;
    speed_mm_s_ = speed_mm_s;
  }
  void Step(float dt_s);
  float position_mm() const { return position_mm_; }
  float encoder_mm() const;  ///< quantised to the encoder's resolution
  bool moving() const { return position_mm_ != target_mm_; }

 private:
  float position_mm_ = 0, target_mm_ = 0, speed_mm_s_ = 1;
};

}  // namespace palpa::sim
