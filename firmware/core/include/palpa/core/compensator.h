// Hysteresis compensators: a finger's target → the drive pressure that produces it, with memory.
//
// All work in the drive domain u ≥ 0 (chamber pressure for pneumatic fingers, vacuum magnitude
// for jamming fingers) and in the finger's output unit y. Their memory is updated from the drive
// pressure actually applied, never from what they asked for, so a slewed, clamped or lagging
// line keeps the model in step with the actuator. Pure and freestanding: no heap, bounded cost.
#pragma once

#include <cstdint>

#include "palpa/protocol/messages_config.h"

namespace palpa::core {

inline constexpr uint8_t kMaxPlayOperators = 32;
inline constexpr uint8_t kMaxDeadZones = 8;
inline constexpr uint8_t kMaxBranchPoints = 24;

/// Two play operators (2k in the low 16-bit lane, 2k+1 in the high one) with what their analytic
/// inverse needs, precomputed at configuration and scaled to integers so the per-step loop clamps
/// two operators per instruction pair and multiply-adds one or two per instruction.
///
/// Units: drive in `drive_step` Pa; the inverse-domain sums in `sum_step` output units; the
/// inverse states, after dropping the sums' low 16 bits, in 2¹⁶ · `sum_step`.
struct PlayPair {           // in this order: the ARMv7E-M loop loads the last two words first
  uint32_t cumulative = 0;  ///< W_i = w0 + Σ_{j≤i} w_j (sum steps per drive step)
  uint32_t mixed = 0;       ///< W_2k low, w_2k+1 high: the lower operator's state in one SMLAD
  uint32_t weight = 0;      ///< w_i (sum steps per drive step)
  uint32_t inverse_threshold = 0;  ///< r'_i = W_i r_i − Σ_{j≤i} w_j r_j (inverse-state steps)
  uint32_t negative_inverse_threshold = 0;
  uint32_t inverse_weight = 0;      ///< w'_i = −w_i / (W_i W_{i−1}), in `drive_gain` units
  uint32_t threshold = 0;           ///< r_i (drive steps)
  uint32_t negative_threshold = 0;  ///< −r_i
};

/// `pi` and `api`: y = offset + S(w0·u + Σ w_i·play_i(u)), S the identity for `pi` and a
/// superposition of one-sided dead zones for `api` (loops that are not point-symmetric).
struct PlayTable {
  uint8_t operators = 0;
  uint8_t pairs = 0;  ///< (operators + 1) / 2 words of PlayPair and of memory
  uint8_t dead_zones = 0;
  float offset = 0;
  float w0 = 0;
  float drive_step = 0;      ///< Pa per step of the memory and of the applied drive
  float per_drive_step = 0;  ///< 1 / drive_step
  float sum_step = 0;        ///< output units per step of the inverse-domain sums
  float per_sum_step = 0;    ///< 1 / sum_step
  float applied_gain = 0;    ///< W_n in sum steps per drive step: the applied drive's share
  float drive_gain = 0;      ///< Pa per unit of the inverse weights' accumulated sum
  float inverse_gain = 0;    ///< 1/w0 + Σ w'_i: what the inverse states contribute at their centre
  PlayPair pair[kMaxPlayOperators / 2]{};
  // S⁻¹ as a piecewise-linear map: above knot_out[k], v = knot_in[k] + (s − knot_out[k]) ·
  // slope[k].
  float knot_out[kMaxDeadZones + 1]{};
  float knot_in[kMaxDeadZones + 1]{};
  float inverse_slope[kMaxDeadZones + 1]{};
};

/// `branch`: rising and falling inverse curves (y → u) and the reversal rule's band.
struct BranchTable {
  uint8_t points = 0;
  float band = 0;       ///< output span over which a reversal blends from one branch to the other
  float dead_band = 0;  ///< applied-pressure movement (Pa) that counts as a reversal
  float output[kMaxBranchPoints]{};
  float rising[kMaxBranchPoints]{};
  float falling[kMaxBranchPoints]{};
};

struct Compensator {
  protocol::CompensatorKind kind = protocol::CompensatorKind::kNone;
  float drive_limit = 0;  ///< largest drive the driven line allows (Pa, magnitude)
  union {
    PlayTable play;
    BranchTable branch;
  };
  Compensator() : play() {}
};

struct CompensatorState {
  /// Play operators' outputs relative to the last applied drive, in drive steps, two per word
  /// as PlayPair: z_i = (applied_steps + lane_i) · drive_step.
  uint32_t play[kMaxPlayOperators / 2]{};
  int32_t applied_steps = 0;  ///< last applied drive, in drive steps
  bool rising = true;         ///< branch: which curve is active
  float extreme = 0;          ///< branch: applied drive at the last turning point so far
  float reversal_output = 0;  ///< branch: output where the active branch started
};

/// Why a parameter set cannot be inverted, or nullptr when it is valid.
const char* CompensatorParamsError(const protocol::ConfigureFinger& finger);

/// Builds the run-time tables; the parameters must have passed CompensatorParamsError.
Compensator MakeCompensator(const protocol::ConfigureFinger& finger, float drive_limit);

/// Memory of a vented chamber (or released vacuum): where every compensator starts.
void HomeCompensator(const Compensator& c, CompensatorState& s);

struct CompensatorOutput {
  float drive = 0;         ///< Pa ≥ 0
  bool saturated = false;  ///< the model asked for more than [0, drive_limit]
};

/// One step: memory ← applied drive, then target → drive. `target` > 0 (callers map 0 to 0 Pa).
CompensatorOutput StepCompensator(const Compensator& c, CompensatorState& s, float target,
                                  float applied_drive);

/// Forward model of `pi`/`api` from the current memory: the output the drive u would give.
/// Used by tests and identification to check the inverse; does not change the memory.
float PlayForward(const Compensator& c, const CompensatorState& s, float u);

/// Play operator i's output (Pa) in the memory of `pi`/`api`.
float PlayState(const Compensator& c, const CompensatorState& s, uint8_t i);

}  // namespace palpa::core
