// The unit of every numeric field of a calibration file (schema 2): one unit per quantity across
// the file — the board's own (Pa, µm, mN/mm, mN) — so nothing in it needs a conversion to be
// compared with anything else in it or uploaded. docs/calibration.md's schema table is this one.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "palpa/protocol/enums.h"

namespace palpa::host {

/// A numeric field by its path ("curve[].drive_pa": `[]` for every element of an array) and its
/// unit on a pneumatic and on a jamming finger ("output" differs: µm of deformation or mN/mm of
/// stiffness, as the board's targets). Counts and identifiers have units of their own ("count",
/// "index", "id"), dimensionless ratios "1".
struct CalibrationField {
  const char* path;
  const char* pneumatic;
  const char* jamming;
  const char* meaning;  ///< what it is, for the schema table
};

/// Every numeric field a calibration file may hold, except `compensator.params[]` (below) and
/// `quality.checks[].value` and `.limit` (their check's unit, CheckUnit).
std::span<const CalibrationField> CalibrationFields();

/// The unit of `path` on a finger of this kind; empty for a path the schema does not have.
std::string CalibrationFieldUnit(const std::string& path, protocol::FingerKind kind);

/// The unit of a quality check's value and limit: points "count", noise and force_zero "mN",
/// leak and previous "1" (a ratio to what is allowed); empty for an unknown check.
std::string CheckUnit(const std::string& name);

/// The unit of each of a compensator's parameters, in the layout ConfigureFinger takes
/// (docs/hysteresis.md): thresholds and the dead band in Pa, the offset, dead-zone knots, band
/// and curve outputs in the output unit, weights in the output unit per Pa, dead-zone slopes "1",
/// api's operator count "count". Empty where the layout does not parse.
std::vector<std::string> CompensatorParamUnits(protocol::CompensatorKind kind,
                                               const std::vector<float>& params,
                                               protocol::FingerKind finger);

}  // namespace palpa::host
