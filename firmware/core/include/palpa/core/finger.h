// A finger: target mode (compensator → line setpoints, with homing) or raw mode. Pure: no I/O.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/compensator.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::core {

/// Per-finger constants derived from a ConfigureFinger when it is applied.
struct FingerParams {
  protocol::FingerKind kind = protocol::FingerKind::kPneumatic;
  protocol::CompensatorKind compensator = protocol::CompensatorKind::kNone;
  uint8_t line_a = 0;
  uint8_t line_b = protocol::kNoLine;
  uint8_t driven_line = 0;  ///< the line the target drives: line_b on a jamming finger, else line_a
  uint8_t bias_line = protocol::kNoLine;  ///< line_a on a jamming finger (held at bias_pa)
  /// +1 where the drive is a pressure, −1 where it is a vacuum magnitude (jamming): the drive
  /// domain of the compensators is ≥ 0, drive = sign × line pressure.
  float drive_sign = 1;
  float bias_pa = 0;
  uint8_t inverse_count = 0;
  std::array<float, protocol::kMaxInversePoints> inverse_output{};
  std::array<float, protocol::kMaxInversePoints> inverse_setpoint{};
  int32_t max_target = 0;    ///< largest output the inverse covers; beyond it targets are refused
  Compensator compensation;  ///< tables of branch / pi / api (unused for none)
};

/// `drive_limit_pa`: the magnitude the driven line's limits allow (pressure, or vacuum).
FingerParams MakeFingerParams(const protocol::ConfigureFinger& finger, float drive_limit_pa);

protocol::OutputUnit UnitOf(protocol::FingerKind kind);

enum class HomePhase : uint8_t { kNeedsHoming, kHoming, kHomed };

struct FingerState {
  protocol::FingerMode mode = protocol::FingerMode::kTarget;
  float target = 0;  ///< in the finger's output unit
  HomePhase phase = HomePhase::kNeedsHoming;
  uint64_t homed_at_us = 0;  ///< when the homing dwell ends
  CompensatorState memory;
};

/// The finger must re-home before following targets again (leaving the safe state, switching
/// back to target mode, new configuration).
inline void RequireHoming(FingerState& s) { s.phase = HomePhase::kNeedsHoming; }

/// What every finger's step shares in a tick: the time, the homing dwell, and where the
/// setpoints and status bits of the lines go (indexed by line).
struct FingerTick {
  uint64_t now_us = 0;
  uint32_t home_dwell_us = 0;
  float* setpoints = nullptr;
  uint8_t* line_status = nullptr;
};

/// One tick in target mode: writes the setpoint of each of the finger's lines and the status bit
/// it adds to its driven line (line_status::kSaturated when the compensator's drive was clamped
/// to the line's range, else 0). `applied_pa` is the pressure actually applied on the driven
/// line (measured, or the regulator model where there is no sensor; negative on a vacuum line):
/// compensators with memory update from it, not from what they asked for.
void StepFinger(const FingerParams& p, FingerState& s, float applied_pa, const FingerTick& tick);

/// The static inverse: output unit → line setpoint; target 0 → 0 Pa.
float StaticInverse(const FingerParams& p, float target);

}  // namespace palpa::core
