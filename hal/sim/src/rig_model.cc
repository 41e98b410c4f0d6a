// Contact between the rig's indenter and a simulated fingertip.
#include "palpa/hal/sim/rig_model.h"

#include <algorithm>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;

RigModel::RigModel(Plant& plant, uint8_t finger, uint32_t seed, float start_mm)
    : plant_(plant),
      finger_(finger),
      force_(plant.options().level < 3, seed),
      stop_sensor_(plant.options().level < 3, seed * 69069u + 1u),
      repeat_rng_(seed * 48271u + 7u) {
  if (plant.options().level >= 3) {
    std::normal_distribution<float> repeat(0.0f, p::kRigRepeatability);
    touch_error_ = repeat(repeat_rng_);
  }
  stage_.MoveTo(start_mm, 1000.0f);
  stage_.Step(1.0f);
}

void RigModel::Step(float dt_s) {
  stage_.Step(dt_s);
  const float tip = stage_.position_mm();
  if (JammingActuator* jamming = plant_.jamming(finger_)) {
    // The granular surface stays at 0; a press loads on the way down and unloads on the way up
    // along the material's loop (DESIGN §5 (a)).
    const float depth = std::max(0.0f, -tip);
    if (depth <= 0) press_max_depth_mm_ = 0;
    press_max_depth_mm_ = std::max(press_max_depth_mm_, depth);
    const bool loading = depth >= last_depth_mm_ && depth >= press_max_depth_mm_;
    true_force_n_ = depth > 0 ? jamming->PressForce(depth, press_max_depth_mm_, loading) : 0.0f;
    true_force_n_ = std::max(0.0f, true_force_n_);
    last_depth_mm_ = depth;
  } else {
    // The film's bump rises to the deformation; the soft contact pushes back linearly. Each
    // touch finds it off by the rig's repeatability (thesis: 2.82 % per point), relative.
    const float deformation = plant_.Truth().fingers[finger_].deformation_mm;
    const float surface = deformation * (1.0f + touch_error_);
    true_force_n_ = p::kRigContactStiffnessNPerMm * std::max(0.0f, surface - tip);
    if (true_force_n_ > 0) touched_ = true;
    if (touched_ && tip - surface > kNewTouchMm && plant_.options().level >= 3) {
      // The indenter went well clear: the next touch is another reading. Backing off a little
      // to creep onto the surface again is the same touch (the reading does not jump under it).
      std::normal_distribution<float> repeat(0.0f, p::kRigRepeatability);
      next_error_ = repeat(repeat_rng_);
      next_pending_ = true;
      touched_ = false;
    }
    // The next touch's error takes over once the indenter is clear of the surface it puts: at
    // once, a surface moved up by it could land on the indenter just gone clear, a touch no
    // motion made, and whether it did would turn on a fraction of a micrometre of travel.
    if (next_pending_ && tip > deformation * (1.0f + next_error_)) {
      touch_error_ = next_error_;
      next_pending_ = false;
    }
  }
  // The controller reads its load cell every step, armed or not, so its readings follow the
  // rig's clock alone.
  stop_readings_[stop_next_] = stop_sensor_.Read(true_force_n_);
  stop_next_ = (stop_next_ + 1) % kStopFilter;
  stop_taken_ = std::min(stop_taken_ + 1, kStopFilter);
  if (stop_force_n_ > 0 && stage_.moving() && stop_taken_ == kStopFilter) {
    float mean = 0;
    for (float f : stop_readings_) mean += f / kStopFilter;
    if (mean >= stop_force_n_) {
      stage_.MoveTo(stage_.position_mm(), 1.0f);
      stop_force_n_ = 0;
    }
  }
}

}  // namespace palpa::sim
