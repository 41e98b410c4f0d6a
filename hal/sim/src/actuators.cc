// Pneumatic deformation and jamming stiffness models (level 2), with their numbers from
// plant_params.json.
#include "palpa/hal/sim/actuators.h"

#include <algorithm>
#include <cmath>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;
namespace {

float Gaussian(float x, float center, float sigma) {
  const float z = (x - center) / sigma;
  return std::exp(-0.5f * z * z);
}

/// The pneumatic film's density: narrow loops near the diagonal whose weight grows with the
/// mean of alpha and beta — a shape no sum of play operators (which see only alpha - beta) makes.
/// A unit's growth adds weight towards the top of the range and its width widens the loops.
float PneumaticDensity(const PneumaticUnit& unit, float alpha, float beta) {
  const float mean = 0.5f * (alpha + beta);
  return p::kPneumaticDensityAmplitudeMm * (1.0f + unit.growth * mean / 100.0f) *
         Gaussian(alpha - beta, p::kPneumaticDensityWidthCenterKpa,
                  p::kPneumaticDensityWidthSigmaKpa * unit.width) *
         Gaussian(mean, p::kPneumaticDensityMeanCenterKpa, p::kPneumaticDensityMeanSigmaKpa);
}

/// Granule packing memory: wide loops centred mid-range.
float HistoryDensity(float alpha, float beta) {
  return Gaussian(alpha - beta, 30.0f, 20.0f) * Gaussian(0.5f * (alpha + beta), 50.0f, 25.0f);
}

}  // namespace

PneumaticActuator::PneumaticActuator(PneumaticUnit unit, Effects effects)
    : unit_gain_(unit.gain),
      effects_(effects),
      loop_(std::make_shared<PreisachModel>(
          static_cast<int>(p::kPneumaticPreisachCells), 100.0f,
          [unit](float alpha, float beta) { return PneumaticDensity(unit, alpha, beta); })) {}

void PneumaticActuator::Reset() {
  loop_->Reset();
  rate_kpa_ = 0;
  creep_mm_ = 0;
  deformation_mm_ = 0;
}

float PneumaticActuator::Reversible(float kpa) const {
  const float x = std::max(0.0f, kpa - p::kPneumaticReversibleDeadZoneKpa);
  return p::kPneumaticReversibleLinearMmPerKpa * x +
         p::kPneumaticReversibleQuadraticMmPerKpa2 * x * x;
}

float PneumaticActuator::RisingMajorMm(float kpa) const {
  return unit_gain_ * (Reversible(kpa) + loop_->RisingMajor(kpa));
}

float PneumaticActuator::FallingMajorMm(float kpa) const {
  return unit_gain_ * (Reversible(kpa) + loop_->FallingMajor(kpa));
}

float PneumaticActuator::Step(float chamber_pa, float dt_s) {
  const float kpa = std::clamp(chamber_pa / 1000.0f, 0.0f, 100.0f);
  // Rate dependence: the film lags fast inputs, which widens the loop at speed.
  if (effects_.rate) {
    rate_kpa_ += (kpa - rate_kpa_) * dt_s / (p::kPneumaticRateTauS + dt_s);
  } else {
    rate_kpa_ = kpa;
  }
  const float instant = unit_gain_ * (Reversible(rate_kpa_) + loop_->Apply(rate_kpa_));
  if (effects_.creep) {
    // A fraction of every change arrives with the creep time constant.
    creep_mm_ +=
        (p::kPneumaticCreepFraction * instant - creep_mm_) * dt_s / (p::kPneumaticCreepTauS + dt_s);
    deformation_mm_ = (1.0f - p::kPneumaticCreepFraction) * instant + creep_mm_;
  } else {
    deformation_mm_ = instant;
  }
  return deformation_mm_;
}

JammingActuator::JammingActuator(float unit_gain, Effects effects)
    : unit_gain_(unit_gain),
      effects_(effects),
      history_fraction_(effects.history >= 0 ? effects.history : p::kJammingHistoryFraction),
      history_(std::make_shared<PreisachModel>(40, 100.0f, HistoryDensity)) {
  float widest = 0;
  for (int x = 0; x <= 100; ++x) {
    widest = std::max(widest, history_->FallingMajor(static_cast<float>(x)) -
                                  history_->RisingMajor(static_cast<float>(x)));
  }
  history_norm_ = widest > 0 ? widest : 1.0f;
}

void JammingActuator::Reset() {
  history_->Reset();
  bias_ = vacuum_ = 0;
  stiffness_ = StaticStiffness(0, 0);
}

float JammingActuator::StaticStiffness(float bias_pa, float vacuum_pa) const {
  const float x = std::clamp(-vacuum_pa / 100000.0f, 0.0f, 1.0f);
  const float b = std::clamp(bias_pa / p::kJammingBiasForLinearPa, 0.0f, 1.0f);
  const float c = p::kJammingCurvature;
  const float linear = (1.0f - c) * x + c * x * x;
  // Without bias the granules jam abruptly around mid vacuum: a normalised logistic step.
  auto logistic = [](float v) {
    return 1.0f / (1.0f + std::exp(-(v - p::kJammingNoBiasCenter) / p::kJammingNoBiasWidth));
  };
  const float abrupt = (logistic(x) - logistic(0)) / (logistic(1) - logistic(0));
  // The air cushion by itself: a small rise, nearly all there within a few kPa (§5.4.3: the
  // curves above 0 kPa almost overlap). With vacuum it widens the span, in proportion to the bias.
  auto air = [this](float pa) {
    return p::kJammingBiasAirStiffening * effects_.bias_stiffening *
           (1.0f - std::exp(-std::max(0.0f, pa) / p::kJammingBiasAirSaturationPa));
  };
  const float widening = p::kJammingBiasSpanWidening * effects_.bias_widening;
  // Anchored at the bias the thesis chose (20 kPa): the axis range of Fig 5-36(c) there.
  const float anchor = p::kJammingBiasForLinearPa;
  const float k0 = p::kJammingStiffnessAt0NPerMm * (1.0f + air(bias_pa)) / (1.0f + air(anchor));
  const float span = (p::kJammingStiffnessAtFullVacuumNPerMm - p::kJammingStiffnessAt0NPerMm) *
                     (1.0f + widening * b) / (1.0f + widening);
  return unit_gain_ * (k0 + span * (b * linear + (1.0f - b) * abrupt));
}

float JammingActuator::Step(float bias_pa, float vacuum_pa) {
  bias_ = bias_pa;
  vacuum_ = vacuum_pa;
  const float x = std::clamp(-vacuum_pa / 1000.0f, 0.0f, 100.0f);
  const float memory = history_->Apply(x) - history_->RisingMajor(x);
  const float span = p::kJammingStiffnessAtFullVacuumNPerMm - p::kJammingStiffnessAt0NPerMm;
  stiffness_ = StaticStiffness(bias_pa, vacuum_pa) +
               unit_gain_ * history_fraction_ * span * (memory / history_norm_);
  return stiffness_;
}

float JammingActuator::PressLoopFraction() const {
  const float x = std::clamp(-vacuum_ / 100000.0f, 0.0f, 1.0f);
  const float b = std::clamp(bias_ / p::kJammingBiasForLinearPa, 0.0f, 1.0f);
  const float growth =
      1.0f + p::kJammingPressLoopGrowthBeyond60kpa * std::max(0.0f, (x - 0.6f) / 0.4f);
  return p::kJammingPressLoopFraction * growth * (1.0f - p::kJammingPressLoopBiasReduction * b);
}

float JammingActuator::PressForce(float depth_mm, float max_depth_mm, bool loading) const {
  const float d = std::clamp(depth_mm, 0.0f, max_depth_mm);
  const float k = stiffness_;
  const float s = p::kJammingPressStiffeningPerMm;
  const float load = k * d * (1.0f + s * d);
  if (loading || max_depth_mm <= 0) return load;
  const float D = max_depth_mm;
  const float work = k * (D * D / 2.0f + s * D * D * D / 3.0f);
  const float area = PressLoopFraction() * work;
  // Loop shape: zero at both ends, ∫ = area; d² makes it vanish faster than the load near 0.
  const float loss = 12.0f * area * d * d * (D - d) / (D * D * D * D);
  return load - loss;
}

}  // namespace palpa::sim
