// The compensator parameter layouts of ConfigureFinger.params, one definition for the board
// (validation, tables), calibration (fits) and the host:
//
//   pi:     [offset, w0, r_1..r_n, w_1..w_n]                             n = 1..32 operators
//   api:    [n, offset, w0, r_1..r_n, w_1..w_n, d_1..d_m, g_1..g_m]      m = 1..8 dead zones
//   branch: [band, dead_band, y_1..y_K, rising_1..rising_K, falling_1..falling_K]  K = 2..24
//
// Reading checks the shape only (counts); what makes a set invalid beyond that (thresholds out of
// order, an inverse that overflows) is the board's to judge (core::CompensatorParamsError).
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/enums.h"

namespace palpa::protocol {

inline constexpr uint8_t kMaxPlayOperators = 32;
inline constexpr uint8_t kMaxDeadZones = 8;
inline constexpr uint8_t kMaxBranchPoints = 24;

/// A pi or api parameter set, as pointers into the parameters it was read from (or is written
/// from). `dead_zones`, `dead_zone_thresholds` and `dead_zone_gains` are api's only.
struct PlayParamSet {
  uint8_t operators = 0;
  uint8_t dead_zones = 0;
  float offset = 0;
  float w0 = 0;
  const float* thresholds = nullptr;            ///< r_1..r_n
  const float* weights = nullptr;               ///< w_1..w_n
  const float* dead_zone_thresholds = nullptr;  ///< d_1..d_m
  const float* dead_zone_gains = nullptr;       ///< g_1..g_m
};

/// A branch parameter set, as pointers into its parameters.
struct BranchParamSet {
  uint8_t points = 0;
  float band = 0;       ///< output span over which a reversal blends one branch into the other
  float dead_band = 0;  ///< applied-pressure movement (Pa) that counts as a reversal
  const float* outputs = nullptr;  ///< y_1..y_K
  const float* rising = nullptr;   ///< drives of the rising branch
  const float* falling = nullptr;  ///< drives of the falling branch
};

/// How many parameters a set of this shape takes.
constexpr size_t PlayParamCount(CompensatorKind kind, size_t operators, size_t dead_zones) {
  return kind == CompensatorKind::kAsymmetricPi ? 3 + 2 * operators + 2 * dead_zones
                                                : 2 + 2 * operators;
}
constexpr size_t BranchParamCount(size_t points) { return 2 + 3 * points; }

/// Reads a pi (kPrandtlIshlinskii) or api (kAsymmetricPi) set; nullptr, or why its shape is wrong.
const char* ReadPlayParams(CompensatorKind kind, const float* params, size_t count,
                           PlayParamSet& out);
const char* ReadBranchParams(const float* params, size_t count, BranchParamSet& out);

/// Writes a set in its layout; returns how many parameters, or 0 when `capacity` is too small.
size_t WritePlayParams(CompensatorKind kind, const PlayParamSet& set, float* out, size_t capacity);
size_t WriteBranchParams(const BranchParamSet& set, float* out, size_t capacity);

}  // namespace palpa::protocol
