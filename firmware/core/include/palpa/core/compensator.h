// Hysteresis compensators: a finger's target → the drive pressure that produces it, with memory.
//
// All work in the drive domain u ≥ 0 (chamber pressure for pneumatic fingers, vacuum magnitude
// for jamming fingers) and in the finger's output unit y. Their memory is updated from the drive
// pressure actually applied, never from what they asked for, so a slewed, clamped or lagging
// line keeps the model in step with the actuator. Pure and freestanding: no heap, bounded cost.
#pragma once

#include <cstdint>

#include "palpa/core/internal/compensator_tables.h"  // what the union below holds; not API
#include "palpa/protocol/messages_config.h"

namespace palpa::core {

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

}  // namespace palpa::core
