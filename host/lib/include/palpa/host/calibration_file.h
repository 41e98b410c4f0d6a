// Calibration files: one JSON file per actuator, keyed by its serial. The schema, a loader that
// validates every field and names the one that is wrong, atomic writes, and the directory the
// library looks in. calibration/ writes through this; the device API reads it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::host {

/// Version 4: the chamber models' lag behind the outlet through the tube's law, the one the board
/// shapes steps with (version 3's models hold only the lag behind the regulator model: loaded,
/// never applied, ChamberNote says so). Version 3: the chamber models. Version 2: one unit per
/// quantity, the board's (calibration_units.h). Older files are still read: version 1's units (kPa,
/// mm, N/mm and N beside the board's Pa, µm and mN/mm) converted on loading, and neither carries a
/// chamber model (the finger's steps are not shaped until it is calibrated again; ChamberNote says
/// so).
inline constexpr int kCalibrationSchemaVersion = 4;
/// The largest valid calibration (1024 grid points, 256 curve points, every optional part,
/// pretty-printed) is about 310 KiB.
inline constexpr FileLimits kCalibrationFileLimits{"calibration file", 1024 * 1024};

// Units: every member below is in the file's unit (calibration_units.h): pressures in Pa,
// deformation in µm, stiffness in mN/mm, forces in mN. "Output" is the finger's output unit —
// µm of deformation (pneumatic) or mN/mm of stiffness (jamming) — as the board's targets are.

/// One point of the calibrated output curve: the output the actuator gives at a drive (negative
/// for vacuum), on the mid-line between the rising and falling branches.
struct CurvePoint {
  double drive_pa = 0;
  double output = 0;
};

/// A straight-line fit of one branch, with its goodness.
struct LineFit {
  double slope = 0;      ///< output per Pa (µm/Pa is mm/kPa, the thesis's unit)
  double intercept = 0;  ///< output
  double r2 = 0;
};

/// One (bias, vacuum) point of an indentation grid: N cycles summarised.
struct GridPoint {
  double bias_pa = 0;
  double vacuum_pa = 0;  ///< negative
  int cycles = 0;
  double stiffness_mean = 0;    ///< mN/mm
  double stiffness_spread = 0;  ///< standard deviation, mN/mm
  double loop_area_mean = 0;    ///< mJ
  double r2_min = 0;
};

/// One failure detector's verdict: its figure against its limit (docs/calibration.md), both in
/// the check's unit (CheckUnit: a count, mN, or a ratio).
struct QualityCheck {
  std::string name;  ///< points, noise, force_zero, leak, previous
  double value = 0;
  double limit = 0;
  bool passed = true;
  std::string detail;  ///< what was measured, in words
};

struct CalibrationQuality {
  double residual_rms = 0;  ///< the compensator's fit residual, output unit
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

/// A line's chamber dynamics, fitted to its step response on the rig (docs/calibration.md): dead
/// time, the regulator's lag the fit assumed (the line's model_tau_us) and the chamber's behind
/// it; and (version 4 on) the chamber's lag behind the outlet the board's sensor reads, through
/// the tube's law, at the step's mean pressure. Applying the calibration gives the line the
/// tube's lag as chamber_tau_us and the overdrive bound, so the board shapes its steps; a model
/// without the tube's lag (an older file's) shapes nothing (ChamberNote says so).
struct ChamberModel {
  uint8_t line = 0;
  double dead_time_s = 0;
  double regulator_tau_s = 0;
  double chamber_tau_s = 0;
  double fit_rms = 0;       ///< of the normalised step response: a fraction of the step
  double tube_tau_s = 0;    ///< 0: not identified (a file of version 3 or older)
  double tube_fit_rms = 0;  ///< the tube fit's, a fraction of the step
};

/// How far beyond its target a calibrated line's shaped step may drive the regulator.
inline constexpr int32_t kShapingOverdrivePa = 20000;

/// The simulated plant a calibration on palpa-sim's rig was taken on (`--rig sim`): which unit,
/// so evaluations on held-out units can tell their calibrations apart.
struct SimulatedPlant {
  uint32_t actuator_unit = 0;  ///< palpa-sim --unit: 0 nominal, others differ as real units do
  uint32_t seed = 1;           ///< --seed: regulator and sensor units, noise
  int plant_level = 3;         ///< --plant, 0..3
  std::string effects;         ///< --effects as given: empty, or e.g. "creep,rate,history=0.2"
};

struct CalibrationFile {
  int schema_version = kCalibrationSchemaVersion;  ///< as read; always written as the current
  std::string actuator_serial;
  protocol::FingerKind kind = protocol::FingerKind::kPneumatic;
  uint32_t board_id = 0;
  uint8_t finger = 0;
  std::string date;                          ///< ISO 8601, UTC
  std::string rig;                           ///< the rig's name (or "sim")
  std::optional<SimulatedPlant> simulation;  ///< taken on palpa-sim's rig
  // Conditions of the run.
  double speed_um_s = 100;
  double depth_um = 3000;
  int repeats = 0;
  std::optional<double> bias_pa;                   ///< jamming: the bias the curve was taken at
  std::string raw_data;                            ///< CSV file beside this one
  std::vector<CurvePoint> curve;                   ///< strictly monotone in drive and output
  std::optional<LineFit> rising_fit, falling_fit;  ///< pneumatic deformation branches
  std::vector<GridPoint> grid;                     ///< jamming indentation grid
  std::vector<protocol::InversePoint> static_inverse;
  std::vector<RegulatorCorrection>
      regulator_corrections;                 ///< one per line of the finger, at most two
  std::vector<ChamberModel> chamber_models;  ///< version 3 on (the tube's lag: 4); at most two
  protocol::CompensatorKind compensator = protocol::CompensatorKind::kNone;
  std::vector<float> compensator_params;
  std::optional<double> recommended_bias_pa;
  CalibrationQuality quality;
};

/// Parses and validates; a bad file is an invalid argument naming the field (a JSON path) and the
/// rule, e.g. "static_inverse[3].setpoint_pa: -120000 is outside -100000 … 100000".
Result<CalibrationFile> ParseCalibration(const std::string& text);
/// The file read (within its size limit) and parsed; errors start with "PATH: ".
Result<CalibrationFile> LoadCalibration(const std::string& path);

/// Validates and serialises; nothing is written when the calibration is invalid.
Result<std::string> SerializeCalibration(const CalibrationFile& c);
/// Written to a temporary file beside `path`, flushed and renamed: a reader sees the old file or
/// the new one, never half of either (an invalid calibration, or io_error naming the file).
Outcome SaveCalibration(const CalibrationFile& c, const std::string& path);

/// Serials name files: 1–11 characters of [A-Za-z0-9_-] (they also fit ConfigureFinger's field).
bool ValidSerial(const std::string& serial);

/// What is wrong with palpa-sim's effects list ("creep,rate,history=0.2", or empty), naming the
/// item; empty when it is one palpa-sim takes (history a fraction of 0 to 0.5).
std::string SimEffectsError(const std::string& effects);

/// The directory the library looks in: $PALPA_CALIBRATION_DIR, else $XDG_DATA_HOME/palpa/
/// calibrations, else ~/.local/share/palpa/calibrations.
std::string DefaultCalibrationDir();

/// DIR/SERIAL.json.
std::string CalibrationPath(const std::string& dir, const std::string& serial);

/// Loads the calibration of an actuator from `dir`. Status kNotFound when there is none (no file,
/// or a serial that cannot name one); kBadValue ("PATH: field: rule") when there is a file but it
/// is invalid, not a regular file, too large, or for another actuator.
Result<CalibrationFile> FindCalibration(const std::string& dir, const std::string& serial);

/// The curves a calibration gives the stiffness map: its measured curve and its range.
FingerCurves CurvesFromCalibration(const CalibrationFile& c);

/// What applying `c` makes of its finger's record: the static inverse, the compensator and its
/// parameters, and (jamming) the recommended bias. The board's other fields stay as they are.
/// Refused (kBadValue, saying why) when the finger's kind differs from the calibration's or the
/// file holds more inverse points or compensator parameters than a finger record does.
Result<protocol::ConfigureFinger> CalibratedFinger(protocol::ConfigureFinger finger,
                                                   const CalibrationFile& c);

/// What applying `c` makes of line `index`'s record: its regulator correction and its chamber
/// model (step shaping), where the file has them. False (the record untouched) when it has
/// neither for this line; refused (kBadValue) when the correction holds more points than a line
/// record does.
Result<bool> CalibratedLine(const CalibrationFile& c, uint8_t index, protocol::ConfigureLine& line);

/// What a calibration without a chamber model means for the finger's steps (empty when it has one):
/// e.g. "schema version 2 has no chamber model: steps are not shaped until the finger is
/// calibrated again".
std::string ChamberNote(const CalibrationFile& c);

/// The compensator a calibration carries, as people name it: "api(8)", "pi(16)", "branch(12)",
/// "none" (operators or curve points from the parameters' layout, docs/hysteresis.md).
std::string CompensatorLabel(const CalibrationFile& c);

}  // namespace palpa::host
