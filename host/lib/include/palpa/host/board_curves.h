// One curve per finger, the board's: the host maps requests through the static inverse the board
// holds (ConfigureFinger.inverse), and says so when a calibration file disagrees with it.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/host/calibration_file.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::host {

/// Whether the finger's static inverse is the compiled-in nominal one for its kind (thesis Table
/// 5-4's line, or Fig 5-36(c)'s axis range) to within the board's integer rounding.
bool IsNominalInverse(const protocol::ConfigureFinger& finger);

/// The curve the board maps a target through, as the host's stiffness map reads it: the nominal
/// curves when the board holds the nominal inverse, otherwise the inverse's points, (kPa, mm or
/// N/mm), in the inverse's order. `source` says where the points came from.
FingerCurves CurvesFromBoard(const protocol::ConfigureFinger& finger, const std::string& source);

/// How far a calibration file's curve is from the board's static inverse, over the drives both
/// cover: the largest difference of their outputs, in the output unit (µm or mN/mm).
struct CurveComparison {
  bool overlap = false;     ///< false: no drive is covered by both (disagreement is meaningless)
  double disagreement = 0;  ///< output unit
  double at_pa = 0;         ///< the drive where it is largest
};
CurveComparison CompareWithBoard(const CalibrationFile& file,
                                 const protocol::ConfigureFinger& board);

/// A calibration file whose curve disagrees with the board's by more than the file's own fit
/// residual: the host follows the board (it is what the board maps targets through) and says so.
struct CurveWarning {
  uint8_t finger = 0;       ///< 0-based
  std::string file;         ///< the calibration file's path
  std::string board;        ///< the board's curve, in words ("the board's static inverse ...")
  bool overlap = false;     ///< false: the two curves share no drive at all
  double disagreement = 0;  ///< output unit
  double at_pa = 0;
  double residual = 0;  ///< the file's fit residual (RMS), output unit
  std::string unit;     ///< "µm" or "mN/mm"
  std::string message;  ///< all of it in one sentence, naming both
};

/// The largest disagreement a file may have with the board without a warning: its compensator
/// fit's RMS residual, at least one output unit (the board's inverse is whole µm or mN/mm).
double CurveTolerance(const CalibrationFile& file);

}  // namespace palpa::host
