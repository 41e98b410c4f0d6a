// Compensator steps: memory from the applied drive, then the inverse for the target.
#include "palpa/core/compensator.h"

#include "compensator_step.h"
#include "palpa/core/curve.h"
#include "palpa/core/internal/float_ops.h"
#include "play_lanes.h"

namespace palpa::core {
namespace {

using protocol::CompensatorKind;

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
    for (uint8_t k = 0; k < c.play.pairs; ++k) s.play[k] = c.play.pair[k].threshold;
    s.applied_steps = 0;
  } else if (c.kind == CompensatorKind::kBranch) {  // on the rising curve from the bottom
    s.rising = true;
    s.extreme = 0;
    s.reversal_output = c.branch.output[0];
  }
}

CompensatorOutput StepCompensator(const Compensator& c, CompensatorState& s, float target,
                                  float applied_drive) {
  CompensatorOutput out;
  if (c.kind == CompensatorKind::kBranch) {
    FollowBranch(c.branch, s, applied_drive > 0 ? applied_drive : 0.0f);
    // Beyond its curves' ends.
    out.saturated = target > c.branch.output[c.branch.points - 1] || target < c.branch.output[0];
    out.drive = HoldDrive(c, BranchDrive(c.branch, s, target), out.saturated);
  } else {
    out.drive = StepPlayInline(c, s, target, applied_drive, out.saturated);
  }
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
