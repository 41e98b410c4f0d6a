// Knowing when a calibration is bad: five detectors, each a figure a rig can measure against a
// limit from the hardware's class — too few points, force noise beyond the sensor's class, a
// drifting force zero, a line that does not hold its pressure (a leak), and an actuator that is
// no longer the one its previous calibration describes. Verdicts go into the calibration file.
#pragma once

#include <optional>
#include <vector>

#include "palpa/calibration/map_protocols.h"
#include "palpa/host/calibration_file.h"

namespace palpa::calibration {

/// The regulator's class as its data sheet gives it (SMC ITV, control_and_perception.md §1):
/// what its static error may be before a line counts as not holding its pressure.
struct RegulatorClass {
  double full_scale_kpa = 100;
  double gain = 0.01;               ///< ±1 % of the command
  double linearity_fs = 0.01;       ///< ±1 % F.S.
  double repeatability_fs = 0.005;  ///< ±0.5 % F.S. (offsets within it)
  double sensor_fss = 0.0025;       ///< the line's sensor: ±0.25 % of its 103 kPa span
  double sensor_span_kpa = 103.4;
  /// How far short of a command (kPa magnitude) the line may read before it is a leak.
  double AllowedDeficitKpa(double command_kpa) const;
};

/// What a finished run hands the detectors.
struct CheckInputs {
  bool jamming = false;
  double force_noise_class_n = kNano17NoiseN;
  double tare_noise_n = 0;            ///< RMS of readings clear of the finger after the tare
  std::vector<MapPress> map;          ///< jamming: every press of the stiffness map
  std::vector<double> free_readings;  ///< other readings clear of the surface (N, after tare)
  int sweep_points = 0;
  std::vector<host::RegulatorCorrection> corrections;
  RegulatorClass regulator{};
  MapBox box{};
  const host::CalibrationFile* previous = nullptr;  ///< the actuator's last calibration, if any
};

/// Limits (docs/calibration.md says why each is where it is).
inline constexpr int kMinMapConditions = 6;
inline constexpr int kMinSweepPoints = 8;
inline constexpr int kMinPressReadings = 20;
inline constexpr double kNoiseLimitClasses = 3;  ///< noise above 3× the class
inline constexpr double kZeroLimitClasses = 3;  ///< a 10-reading mean off by 3× one reading's noise
inline constexpr double kHeldToleranceKpa = 1.0;  ///< trim on: the supervisor's sensor tolerance
inline constexpr double kSpreadFloor = 0.015;     ///< a calibration's relative spread, at least
inline constexpr double kPreviousLimitSigmas = 3;

/// The force_zero detector alone: the largest reading clear of the surface against its limit.
host::QualityCheck CheckForceZero(const CheckInputs& in);

/// Runs every detector that applies; `fresh` is the new calibration (its curve and map).
std::vector<host::QualityCheck> RunQualityChecks(const CheckInputs& in,
                                                 const host::CalibrationFile& fresh);

}  // namespace palpa::calibration
