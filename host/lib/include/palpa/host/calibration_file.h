// Calibration files: one JSON file per actuator, keyed by its serial. The schema, a loader that
// validates every field and names the one that is wrong, atomic writes, and the directory the
// library looks in. calibration/ writes through this; the device API reads it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::host {

inline constexpr int kCalibrationSchemaVersion = 1;
/// The largest valid calibration (1024 grid points, 256 curve points, every optional part,
/// pretty-printed) is about 310 KiB.
inline constexpr FileLimits kCalibrationFileLimits{"calibration file", 1024 * 1024};

/// One point of the calibrated output curve: the output (mm, or N/mm) the actuator gives at a
/// drive (kPa; negative for vacuum), on the mid-line between the rising and falling branches.
struct CurvePoint {
  double kpa = 0;
  double output = 0;
};

/// A straight-line fit of one branch or condition, with its goodness.
struct LineFit {
  double slope = 0;
  double intercept = 0;
  double r2 = 0;
};

/// One (bias, vacuum) point of an indentation grid: N cycles summarised.
struct GridPoint {
  double bias_kpa = 0;
  double vacuum_kpa = 0;
  int cycles = 0;
  double stiffness_mean = 0;    ///< N/mm
  double stiffness_spread = 0;  ///< standard deviation, N/mm
  double loop_area_mean = 0;    ///< mJ
  double r2_min = 0;
};

/// One failure detector's verdict: its figure against its limit (docs/calibration.md).
struct QualityCheck {
  std::string name;  ///< points, noise, force_zero, leak, previous
  double value = 0;
  double limit = 0;
  bool passed = true;
  std::string detail;  ///< what was measured, in words
};

struct CalibrationQuality {
  double residual_rms = 0;  ///< of the output curve's fit, output unit
  double residual_max = 0;
  int points = 0;                   ///< settled readings the fits used
  std::vector<std::string> flags;   ///< detectors that fired and other warnings (empty: clean)
  std::string protocol;             ///< "thesis" or "adaptive"; empty in older files
  int cycles = 0;                   ///< indentation cycles of the stiffness map
  double rig_time_s = 0;            ///< of the whole run
  std::optional<double> map_error;  ///< jamming: cross-validated map error (fraction of value)
  std::vector<QualityCheck> checks;
};

struct RegulatorCorrection {
  uint8_t line = 0;
  std::vector<protocol::CorrectionPoint> points;  ///< command → measured, rising and falling
};

struct CalibrationFile {
  int schema_version = kCalibrationSchemaVersion;
  std::string actuator_serial;
  protocol::FingerKind kind = protocol::FingerKind::kPneumatic;
  uint32_t board_id = 0;
  uint8_t finger = 0;
  std::string date;  ///< ISO 8601, UTC
  std::string rig;   ///< the rig's name (or "sim")
  // Conditions of the run.
  double speed_mm_s = 0.1;
  double depth_mm = 3;
  int repeats = 0;
  std::optional<double> bias_kpa;                  ///< jamming: the bias the curve was taken at
  std::string raw_data;                            ///< CSV file beside this one
  std::vector<CurvePoint> curve;                   ///< strictly monotone in kpa and output
  std::optional<LineFit> rising_fit, falling_fit;  ///< pneumatic deformation branches
  std::vector<GridPoint> grid;                     ///< jamming indentation grid
  std::vector<protocol::InversePoint> static_inverse;
  std::vector<RegulatorCorrection>
      regulator_corrections;  ///< one per line of the finger, at most two
  protocol::CompensatorKind compensator = protocol::CompensatorKind::kNone;
  std::vector<float> compensator_params;
  std::optional<double> recommended_bias_kpa;
  CalibrationQuality quality;
};

/// Parses and validates; on failure returns nullopt and names the field (a JSON path) and the
/// rule in *error, e.g. "static_inverse[3].setpoint_pa: -120000 is outside -100000 … 100000".
std::optional<CalibrationFile> ParseCalibration(const std::string& text, std::string* error);
std::optional<CalibrationFile> LoadCalibration(const std::string& path, std::string* error);

/// Validates and serialises; nothing is written when the calibration is invalid.
std::optional<std::string> SerializeCalibration(const CalibrationFile& c, std::string* error);
/// Written to a temporary file beside `path`, flushed and renamed: a reader sees the old file or
/// the new one, never half of either.
bool SaveCalibration(const CalibrationFile& c, const std::string& path, std::string* error);

/// Serials name files: 1–11 characters of [A-Za-z0-9_-] (they also fit ConfigureFinger's field).
bool ValidSerial(const std::string& serial);

/// The directory the library looks in: $PALPA_CALIBRATION_DIR, else $XDG_DATA_HOME/palpa/
/// calibrations, else ~/.local/share/palpa/calibrations.
std::string DefaultCalibrationDir();

/// DIR/SERIAL.json.
std::string CalibrationPath(const std::string& dir, const std::string& serial);

/// Loads the calibration of an actuator from `dir`. Status kNotFound with *error when there is
/// none (no file, or a serial that cannot name one); kBadValue with *error ("PATH: field: rule")
/// when there is a file but it is invalid, not a regular file, too large, or for another actuator.
protocol::Result<CalibrationFile> FindCalibration(const std::string& dir, const std::string& serial,
                                                  std::string* error);

/// The curves a calibration gives the stiffness map: its measured curve and its range.
FingerCurves CurvesFromCalibration(const CalibrationFile& c);

/// The compensator a calibration carries, as people name it: "api(8)", "pi(16)", "branch(12)",
/// "none" (operators or curve points from the parameters' layout, docs/hysteresis.md).
std::string CompensatorLabel(const CalibrationFile& c);

}  // namespace palpa::host
