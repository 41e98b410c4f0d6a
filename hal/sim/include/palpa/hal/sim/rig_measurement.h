// The rig's view of an actuator: what a contact-detecting linear stage and a Nano17-class force
// sensor report, never the clean truth. Identification and evaluation read outputs through it.
#pragma once

#include <cstdint>
#include <random>

#include "palpa/hal/sim/actuators.h"
#include "palpa/hal/sim/sensors.h"

namespace palpa::sim {

class RigMeasurement {
 public:
  explicit RigMeasurement(uint32_t seed, bool ideal = false);

  /// Finds the surface of a pneumatic finger by contact detection (approach at the thesis's
  /// speed until the force crosses a threshold) and returns its height in mm on the encoder.
  float SurfaceHeight(float true_height_mm);
  /// Deformation in mm: the surface now against the surface found when vented (Zero()). Each
  /// reading is off by the rig's repeatability (thesis: 2.82 % per point), relative to it.
  void Zero(float vented_height_mm) { zero_mm_ = SurfaceHeight(vented_height_mm); }
  float Deformation(float true_deformation_mm);

  /// Stiffness in N/mm from one press of a jamming finger to the set depth: force against depth
  /// from the sensor and encoder, fitted as F = k·d + q·d² (the Hooke's-law slope at contact).
  float Stiffness(const JammingActuator& actuator);

 private:
  ForceSensor force_;
  bool ideal_;
  float zero_mm_ = 0;
  std::mt19937 repeat_rng_;
};

}  // namespace palpa::sim
