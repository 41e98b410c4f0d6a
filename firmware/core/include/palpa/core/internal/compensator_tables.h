// Internal to firmware/core: the compensators' run-time tables — play operators packed two to a
// word as integer lanes for the DSP loop, the api's output map, the branch curves. Built by
// MakeCompensator from a parameter set and read only by the step (and by the board images that
// check the ARMv7E-M loop against the portable one); compensator.h includes this header for the
// size of Compensator, and nothing outside the firmware names what it declares.
#pragma once

#include <cstdint>

#include "palpa/protocol/compensator_params.h"

namespace palpa::core {

inline constexpr uint8_t kMaxPlayOperators = protocol::kMaxPlayOperators;
inline constexpr uint8_t kMaxDeadZones = protocol::kMaxDeadZones;
inline constexpr uint8_t kMaxBranchPoints = protocol::kMaxBranchPoints;

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

struct Compensator;
struct CompensatorState;

/// Play operator i's output (Pa) in the memory of `pi`/`api` (for tests of the memory).
float PlayState(const Compensator& c, const CompensatorState& s, uint8_t i);

}  // namespace palpa::core
