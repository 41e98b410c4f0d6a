// Compensator steps: memory from the applied drive, then the inverse for the target.
#include "palpa/core/compensator.h"

#include "float_ops.h"
#include "palpa/core/curve.h"
#include "play_lanes.h"
#include "play_pairs.h"

namespace palpa::core {
namespace {

using protocol::CompensatorKind;

/// S⁻¹ of the `api` output map (identity when there are no dead zones).
float OutputMapInverse(const PlayTable& t, float s) {
  uint8_t k = t.dead_zones;
  while (k > 0 && s < t.knot_out[k]) --k;
  return t.knot_in[k] + (s - t.knot_out[k]) * t.inverse_slope[k];
}

// Where the inverse-domain sum starts is clamped to ±2³⁰ sum steps: the scales keep the
// operators' shares and every inverse threshold within 2²⁹ (compensator_params.cc), so a
// clamped start still puts each inverse state beyond its threshold (as the true one is) and no
// sum leaves int32.
constexpr float kStartLimit = 1073741824.0f;     // 2³⁰
constexpr float kHalfUpperStep = 32768.0f;       // rounds the states' upper halves to nearest
constexpr float kMaxAppliedSteps = 16777216.0f;  // 2²⁴: exact in float, far beyond any sensor

/// Analytic PI inverse evaluated from the forward memory, two operators per word, top pair
/// first. Each forward operator first follows the applied drive (its memory is kept relative
/// to the last applied drive, so that is one saturating add and a clamp); then its
/// inverse-domain state z'_i − v = (W_n a − v) + W_i c_i + Σ_{j>i} w_j c_j follows the target
/// (a clamp to ±r'_i) and adds w'_i times itself to the drive. No inverse memory is kept that
/// could drift away from what the chamber actually saw.
float PlayStep(const PlayTable& t, CompensatorState& s, float v, float applied) {
  const float a = applied * t.per_drive_step + 0.5f;
  const int32_t applied_steps = static_cast<int32_t>(a < kMaxAppliedSteps ? a : kMaxAppliedSteps);
  // Beyond ±32767 steps every operator ends on its clamp anyway (|r| ≤ 16383 steps).
  const int32_t moved = lanes::Saturate(s.applied_steps - applied_steps);
  s.applied_steps = applied_steps;
  const uint32_t shift = lanes::Pack(moved, moved);
  float start = t.applied_gain * static_cast<float>(applied_steps) - v * t.per_sum_step;
  start = start < -kStartLimit ? -kStartLimit : (start > kStartLimit ? kStartLimit : start);
  const int32_t later = static_cast<int32_t>(start + kHalfUpperStep);
  const int32_t drive =
      PlayPairs(t.pair, s.play, static_cast<uint8_t>((t.operators + 1) / 2), shift, later);
  return static_cast<float>(drive) * t.drive_gain + t.inverse_gain * v;
}

/// Which curve is active follows the applied drive: a move of more than the dead band against
/// the current direction is a reversal, and the output there starts the blend to the other branch.
void FollowBranch(const BranchTable& t, CompensatorState& s, float applied) {
  if (s.rising) {
    if (applied > s.extreme) s.extreme = applied;
    if (applied < s.extreme - t.dead_band) {
      s.reversal_output = Interpolate(t.rising, t.output, t.points, s.extreme);
      s.rising = false;
      s.extreme = applied;
    }
  } else {
    if (applied < s.extreme) s.extreme = applied;
    if (applied > s.extreme + t.dead_band) {
      s.reversal_output = Interpolate(t.falling, t.output, t.points, s.extreme);
      s.rising = true;
      s.extreme = applied;
    }
  }
}

float BranchDrive(const BranchTable& t, const CompensatorState& s, float target) {
  const float on = Interpolate(t.output, s.rising ? t.rising : t.falling, t.points, target);
  const float other = Interpolate(t.output, s.rising ? t.falling : t.rising, t.points, target);
  // Just after a reversal the actuator has not left the old branch: blend across `band`.
  const float travelled = s.rising ? target - s.reversal_output : s.reversal_output - target;
  const float old_share = Clamp(1.0f - travelled / t.band, 0.0f, 1.0f);
  return on + (other - on) * old_share;
}

}  // namespace

void HomeCompensator(const Compensator& c, CompensatorState& s) {
  if (c.kind == CompensatorKind::kPrandtlIshlinskii || c.kind == CompensatorKind::kAsymmetricPi) {
    // Vented from any height: every operator rests on its upper clamp at u = 0, which is also
    // where one-sided drive always returns it (the chamber's memory is wiped at 0).
    for (uint8_t k = 0; k < (c.play.operators + 1) / 2; ++k) s.play[k] = c.play.pair[k].threshold;
    s.applied_steps = 0;
  } else if (c.kind == CompensatorKind::kBranch) {  // on the rising curve from the bottom
    s.rising = true;
    s.extreme = 0;
    s.reversal_output = c.branch.output[0];
  }
}

CompensatorOutput StepCompensator(const Compensator& c, CompensatorState& s, float target,
                                  float applied_drive) {
  const float applied = applied_drive > 0 ? applied_drive : 0.0f;
  float drive = 0;
  bool outside = false;  // beyond what the model was identified over
  if (c.kind == CompensatorKind::kBranch) {
    FollowBranch(c.branch, s, applied);
    drive = BranchDrive(c.branch, s, target);
    // Beyond its curves' ends.
    outside = target > c.branch.output[c.branch.points - 1] || target < c.branch.output[0];
  } else {
    const float v = OutputMapInverse(c.play, target - c.play.offset);
    drive = PlayStep(c.play, s, v, applied);
  }
  CompensatorOutput out;
  out.saturated = outside;
  // A model asked for what the line cannot give (or for less than nothing): held at the limit,
  // and said so. NaN cannot pass configuration, but the guard costs one compare.
  if (!(drive >= 0)) {
    out.saturated = out.saturated || drive < -1.0f || drive != drive;
    drive = 0;
  } else if (drive > c.drive_limit) {
    out.saturated = true;
    drive = c.drive_limit;
  }
  out.drive = drive;
  return out;
}

float PlayState(const Compensator& c, const CompensatorState& s, uint8_t i) {
  return static_cast<float>(s.applied_steps + lanes::Lane(s.play[i / 2], i)) * c.play.drive_step;
}

float PlayForward(const Compensator& c, const CompensatorState& s, float u) {
  const PlayTable& t = c.play;
  const float weight_unit = t.sum_step * t.per_drive_step;  // output units per Pa per weight step
  float v = t.w0 * u;
  for (uint8_t i = 0; i < t.operators; ++i) {
    const PlayPair& pair = t.pair[i / 2];
    const float r = static_cast<float>(lanes::Lane(pair.threshold, i)) * t.drive_step;
    const float w = static_cast<float>(lanes::Lane(pair.weight, i)) * weight_unit;
    v += w * Clamp(PlayState(c, s, i), u - r, u + r);
  }
  // S(v): back through the knots of S⁻¹.
  uint8_t k = t.dead_zones;
  while (k > 0 && v < t.knot_in[k]) --k;
  return t.offset + t.knot_out[k] + (v - t.knot_in[k]) / t.inverse_slope[k];
}

}  // namespace palpa::core
