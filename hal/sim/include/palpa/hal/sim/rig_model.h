// The calibration rig around one finger of the simulated plant: a linear stage carrying an 8 mm
// hemispherical indenter above the fingertip, and a Nano17-class force sensor under it. Stepped
// with the plant (1 ms), so the rig and the board share one clock. Host only.
#pragma once

#include <cstdint>
#include <random>

#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/sensors.h"

namespace palpa::sim {

class RigModel {
 public:
  /// `finger` of `plant`; the indenter starts `start_mm` above the vented surface.
  RigModel(Plant& plant, uint8_t finger, uint32_t seed, float start_mm = 5.0f);

  /// Advances the stage and the contact by dt.
  void Step(float dt_s);

  LinearStage& stage() { return stage_; }
  /// Indenter tip height above the vented surface (mm): the stage's encoder reading.
  float PositionMm() const { return stage_.encoder_mm(); }
  /// What the force sensor reads now (N, compressive positive, after its tare).
  float ReadForceN() { return force_.Read(true_force_n_); }
  void Tare() {
    force_.Tare(true_force_n_);
    stop_sensor_.Tare(true_force_n_);
  }
  /// The stage controller's force-limit stop: the stage stops itself at the first step its
  /// filtered force reading reaches `n` (N, after the tare), then the limit is disarmed; 0 disarms
  /// it. Judged on the rig's own clock, so where it stops does not depend on the host.
  void StopOnForce(float n) {
    stop_force_n_ = n;
    stop_taken_ = 0;  // judged on readings taken since: none from before the move counts
  }
  /// The true contact force (N), for scoring and the rig's own safety model only.
  float true_force_n() const { return true_force_n_; }

 private:
  Plant& plant_;
  uint8_t finger_;
  LinearStage stage_;
  ForceSensor force_;
  /// The controller's own readings of the load cell, one per step (a stream of their own, so
  /// the host's readings stay what they were), averaged over kStopFilter steps of the move.
  static constexpr int kStopFilter = 8;
  ForceSensor stop_sensor_;
  float stop_readings_[kStopFilter] = {};
  int stop_next_ = 0;
  int stop_taken_ = 0;  ///< readings since the limit was armed
  float stop_force_n_ = 0;
  float true_force_n_ = 0;
  float press_max_depth_mm_ = 0;  ///< deepest point of the current press (jamming)
  float last_depth_mm_ = 0;
  /// A pneumatic film's reading is off by the rig's repeatability, relative, drawn per touch.
  std::mt19937 repeat_rng_;
  float touch_error_ = 0;
  float next_error_ = 0;  ///< drawn when a touch ended, in force once the indenter is clear of it
  bool next_pending_ = false;
  bool touched_ = false;
  /// A touch ends when the indenter is this far above the surface (a new approach).
  static constexpr float kNewTouchMm = 0.1f;
};

}  // namespace palpa::sim
