// Contact detection and press regression with the rig's sensor noise and resolution.
#include "palpa/hal/sim/rig_measurement.h"

#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;

RigMeasurement::RigMeasurement(uint32_t seed, bool ideal)
    : force_(ideal, seed), ideal_(ideal), repeat_rng_(seed * 48271u + 7u) {}

float RigMeasurement::Deformation(float true_deformation_mm) {
  float reading = true_deformation_mm;
  if (!ideal_) {
    std::normal_distribution<float> repeat(0.0f, p::kRigRepeatability);
    reading *= 1.0f + repeat(repeat_rng_);
  }
  return SurfaceHeight(reading) - zero_mm_;
}

float RigMeasurement::SurfaceHeight(float true_height_mm) {
  if (ideal_) return true_height_mm;
  constexpr float kDt = 0.001f;
  constexpr float kStartAboveMm = 0.05f;
  // Start just above the surface (a coarse move got here) and creep down at the set speed.
  const float start = std::round((true_height_mm + kStartAboveMm) / p::kRigStageResolutionMm) *
                      p::kRigStageResolutionMm;
  float position = start;
  for (int k = 0; k < 20000; ++k) {
    position -= p::kRigApproachSpeedMmS * kDt;
    const float indentation = std::max(0.0f, true_height_mm - position);
    if (force_.Read(p::kRigContactStiffnessNPerMm * indentation) >= p::kRigContactThresholdN) break;
  }
  return std::round(position / p::kRigStageResolutionMm) * p::kRigStageResolutionMm;
}

float RigMeasurement::Stiffness(const JammingActuator& actuator) {
  const float depth = p::kRigPressDepthMm;
  // One sample per 10 µm of travel: 300 points over a 3 mm press.
  double s11 = 0, s12 = 0, s22 = 0, b1 = 0, b2 = 0;
  for (int k = 1; k <= 300; ++k) {
    const float d = std::round(depth * static_cast<float>(k) / 300.0f / p::kRigStageResolutionMm) *
                    p::kRigStageResolutionMm;
    const double f = force_.Read(actuator.PressForce(d, depth, true));
    s11 += static_cast<double>(d) * d;
    s12 += static_cast<double>(d) * d * d;
    s22 += static_cast<double>(d) * d * d * d;
    b1 += d * f;
    b2 += static_cast<double>(d) * d * f;
  }
  const double det = s11 * s22 - s12 * s12;
  return static_cast<float>((b1 * s22 - b2 * s12) / det);
}

}  // namespace palpa::sim
