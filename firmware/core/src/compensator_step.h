// The play-operator compensators' step (pi, api), inlined into the finger step (a call and a
// struct return per finger per tick otherwise); the branch model's stays in compensator.cc.
#pragma once

#include "palpa/core/compensator.h"
#include "palpa/core/internal/float_ops.h"
#include "play_lanes.h"
#include "play_pairs.h"

namespace palpa::core {
namespace compensator_step {

/// S⁻¹ of the `api` output map (identity when there are no dead zones).
inline float OutputMapInverse(const PlayTable& t, float s) {
  uint8_t k = t.dead_zones;
  while (k > 0 && s < t.knot_out[k]) --k;
  return t.knot_in[k] + (s - t.knot_out[k]) * t.inverse_slope[k];
}

constexpr float kHalfUpperStep = 32768.0f;     // rounds the states' upper halves to nearest
constexpr int32_t kMaxAppliedSteps = 1 << 24;  // exact in float, far beyond any sensor

/// Analytic PI inverse evaluated from the forward memory, two operators per word, top pair
/// first. Each forward operator first follows the applied drive (its memory is kept relative
/// to the last applied drive, so that is one saturating add and a clamp); then its
/// inverse-domain state z'_i − v = (W_n a − v) + W_i c_i + Σ_{j>i} w_j c_j follows the target
/// (a clamp to ±r'_i) and adds w'_i times itself to the drive. No inverse memory is kept that
/// could drift away from what the chamber actually saw. A negative applied drive counts as 0.
/// The conversions saturate (one instruction each on the Cortex-M4F) and the results are then
/// held in integers.
inline float PlayStep(const PlayTable& t, CompensatorState& s, float v, float applied) {
  int32_t applied_steps = TruncateSaturating(applied * t.per_drive_step + 0.5f);
  applied_steps = applied_steps < 0 ? 0 : applied_steps;
  applied_steps = applied_steps > kMaxAppliedSteps ? kMaxAppliedSteps : applied_steps;
  // Beyond ±32767 steps every operator ends on its clamp anyway (|r| ≤ 16383 steps).
  const int32_t moved = lanes::Saturate(s.applied_steps - applied_steps);
  s.applied_steps = applied_steps;
  const uint32_t shift = lanes::Pack(moved, moved);
  // Where the inverse-domain sum starts is held to ±2³⁰ sum steps: the scales keep the operators'
  // shares and every inverse threshold within 2²⁹ (compensator_params.cc), so a start held there
  // still puts each inverse state beyond its threshold (as the true one is) and no sum leaves
  // int32.
  const float start = t.applied_gain * static_cast<float>(applied_steps) - v * t.per_sum_step;
  const int32_t later = lanes::Saturate31(TruncateSaturating(start + kHalfUpperStep));
  const int32_t drive = PlayPairs(t.pair, s.play, t.pairs, shift, later);
  return static_cast<float>(drive) * t.drive_gain + t.inverse_gain * v;
}

}  // namespace compensator_step

/// The drive a model asked for, held to [0, drive_limit]: a model asked for what the line cannot
/// give (or for less than nothing), held at the limit, and said so in `saturated`. NaN cannot
/// pass configuration, but the guard costs one compare.
[[gnu::always_inline]] inline float HoldDrive(const Compensator& c, float drive, bool& saturated) {
  if (!(drive >= 0)) {
    saturated = saturated || drive < -1.0f || drive != drive;
    return 0;
  }
  if (drive > c.drive_limit) {
    saturated = true;
    return c.drive_limit;
  }
  return drive;
}

/// The `pi` / `api` step (StepCompensator's contract): the drive, held to [0, drive_limit], and
/// `saturated` when it was held. Inlined into the finger step.
[[gnu::always_inline]] inline float StepPlayInline(const Compensator& c, CompensatorState& s,
                                                   float target, float applied_drive,
                                                   bool& saturated) {
  const float shifted = target - c.play.offset;
  // Without dead zones S⁻¹ is the identity (pi, and api fitted without them).
  const float v =
      c.play.dead_zones == 0 ? shifted : compensator_step::OutputMapInverse(c.play, shifted);
  saturated = false;
  return HoldDrive(c, compensator_step::PlayStep(c.play, s, v, applied_drive), saturated);
}

}  // namespace palpa::core
