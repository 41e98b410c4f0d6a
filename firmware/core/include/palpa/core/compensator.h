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

/// One play operator of the forward model with what its analytic inverse needs, precomputed at
/// configuration so the per-step loop is multiply-adds and clamps only.
struct PlayOperator {
  float threshold = 0;          ///< r_i (Pa)
  float weight = 0;             ///< w_i
  float cumulative = 0;         ///< W_i = w0 + Σ_{j≤i} w_j: maps forward state to inverse state
  float inverse_threshold = 0;  ///< r'_i = W_i r_i − Σ_{j≤i} w_j r_j
  float half_inverse_weight = 0;  ///< w'_i / 2, w'_i = −w_i / (W_i W_{i−1})
};

/// `pi` and `api`: y = offset + S(w0·u + Σ w_i·play_i(u)), S the identity for `pi` and a
/// superposition of one-sided dead zones for `api` (loops that are not point-symmetric).
struct PlayTable {
  uint8_t operators = 0;
  uint8_t dead_zones = 0;
  float offset = 0;
  float w0_inverse = 0;
  float inverse_gain = 0;  ///< 1/w0 + Σ w'_i: what the inverse states contribute at their centre
  PlayOperator op[kMaxPlayOperators]{};
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
  float z[kMaxPlayOperators]{};  ///< play operator outputs (forward model, drive domain)
  bool rising = true;            ///< branch: which curve is active
  float extreme = 0;             ///< branch: applied drive at the last turning point so far
  float reversal_output = 0;     ///< branch: output where the active branch started
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

}  // namespace palpa::core
