// Compensator steps: memory from the applied drive, then the inverse for the target.
#include "palpa/core/compensator.h"

#include "palpa/core/curve.h"

namespace palpa::core {
namespace {

using protocol::CompensatorKind;

inline float Clamp(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

/// S⁻¹ of the `api` output map (identity when there are no dead zones).
float OutputMapInverse(const PlayTable& t, float s) {
  uint8_t k = t.dead_zones;
  while (k > 0 && s < t.knot_out[k]) --k;
  return t.knot_in[k] + (s - t.knot_out[k]) * t.inverse_slope[k];
}

/// ½(|d + r| − |d − r|) = clamp(d, −r, r) for r ≥ 0: two absolute values instead of two
/// compare-and-select pairs, because the Cortex-M4's FPU has no min or max.
inline float HalfBand(float d, float r) { return __builtin_fabsf(d + r) - __builtin_fabsf(d - r); }

/// Analytic PI inverse evaluated from the forward memory. One backward pass does both jobs:
/// each play operator first follows the applied drive, then its inverse-domain state
/// z'_i = W_i z_i + Σ_{j>i} w_j z_j follows the target — so no inverse memory is kept that
/// could drift away from what the chamber actually saw. Clamped states are written as centre +
/// half band, so the centres' share of the sum is the precomputed inverse_gain · v.
float PlayStep(const PlayTable& t, float* z, float v, float applied) {
  float later = -v;  // Σ_{j>i} w_j z_j − v: the inverse state's offset from the target
  float drive = 0;
  const PlayOperator* op = t.op + t.operators;
  float* zi = z + t.operators;
  while (op != t.op) {
    --op;
    --zi;
    const float state = applied + 0.5f * HalfBand(*zi - applied, op->threshold);
    *zi = state;
    const float inverse_offset = op->cumulative * state + later;
    later += op->weight * state;
    drive += op->half_inverse_weight * HalfBand(inverse_offset, op->inverse_threshold);
  }
  return drive + t.inverse_gain * v;
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
    for (uint8_t i = 0; i < c.play.operators; ++i) s.z[i] = c.play.op[i].threshold;
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
    outside = target > c.branch.output[c.branch.points - 1] || target < c.branch.output[0];  // its curves' ends
  } else {
    const float v = OutputMapInverse(c.play, target - c.play.offset);
    drive = PlayStep(c.play, s.z, v, applied);
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

float PlayForward(const Compensator& c, const CompensatorState& s, float u) {
  const PlayTable& t = c.play;
  float v = u / t.w0_inverse;
  for (uint8_t i = 0; i < t.operators; ++i) {
    const PlayOperator& op = t.op[i];
    v += op.weight * Clamp(s.z[i], u - op.threshold, u + op.threshold);
  }
  // S(v): back through the knots of S⁻¹.
  uint8_t k = t.dead_zones;
  while (k > 0 && v < t.knot_in[k]) --k;
  return t.offset + t.knot_out[k] + (v - t.knot_in[k]) / t.inverse_slope[k];
}

}  // namespace palpa::core
