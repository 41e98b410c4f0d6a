// What a finger should do, in the terms a person uses — a level, 0..1, N/mm, mm, kPa — mapped to
// what the board takes: a target in the finger's output unit, or raw line setpoints.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/protocol/messages_bootstrap.h"
#include "palpa/protocol/messages_report.h"
#include "palpa/protocol/status.h"

namespace palpa::host {

inline constexpr FileLimits kLevelsFileLimits{"level table file", 64 * 1024};

/// Level tables: per finger kind, the pressure (pneumatic) or vacuum (jamming) of each level.
struct LevelTables {
  std::vector<double> pneumatic_kpa = {0, 10, 30};
  std::vector<double> jamming_kpa = {0, -10, -100};
  double jamming_bias_kpa = 20;
  double jamming_alternative_middle_kpa = -30;

  /// The tables shipped with the library (host/lib/data/levels.json).
  static LevelTables Shipped();
  /// Reads a levels file; a bad file is an invalid argument naming the field.
  static Result<LevelTables> Load(const std::string& path);
};

/// How a finger's output unit relates to pressure: the nominal thesis curves until a
/// calibration replaces them (CurvesFromCalibration in calibration_file.h).
/// What the nominal curves stand on, said with every request that uses them.
inline constexpr const char* kNominalCurvesBasis =
    "Table 5-4's bare film without the top layer; Fig 5-36(c)'s axis range, an assumption";

struct FingerCurves {
  std::string source =
      std::string("nominal thesis curves (no calibration: ") + kNominalCurvesBasis + ")";
  /// A calibration's curve, (kPa, output in mm or N/mm), monotone: when present it replaces the
  /// nominal lines below, read by linear interpolation and never extrapolated.
  std::vector<std::pair<double, double>> calibrated;
  // Pneumatic: deformation (mm) = max(0, slope * kPa + intercept) — Table 5-4, all data, which
  // was measured on the bare film, without the 3 mm top layer worn in service (a film-deformation
  // equivalent, not the height of the surface a finger touches; a calibration measures that).
  double deformation_slope_mm_per_kpa = 0.0458;
  double deformation_intercept_mm = -0.2098;
  double max_deformation_mm = 4.370;
  // Jamming at the bias: stiffness (N/mm) from 0 kPa to full vacuum, near linear. 0.7 and 1.3 are
  // the ends of Fig 5-36(c)'s stiffness axis, not measured end points: an axis-range assumption
  // until a calibration replaces them.
  double stiffness_at_0 = 0.7;
  double stiffness_at_full_vacuum = 1.3;
};

enum class TargetKind { kLevel, kNormalized, kStiffnessNPerMm, kDeformationMm, kPressureKpa };

struct Request {
  TargetKind kind = TargetKind::kLevel;
  double value = 0;
};

/// Beyond the calibrated range a request is refused, or clamped when the caller asks for it;
/// it is never extrapolated silently.
enum class RangePolicy { kRefuse, kClamp };

struct Mapped {
  protocol::Status status = protocol::Status::kOk;
  std::string error;   ///< for people: what was wrong and what was expected
  bool raw = false;    ///< raw mode: line setpoints; otherwise a target in the output unit
  int32_t target = 0;  ///< µm (pneumatic) or mN/mm (jamming)
  int32_t line_a_pa = 0, line_b_pa = 0;  ///< raw mode
  std::string note;  ///< e.g. which curves were used, or that the value was clamped
  /// A level: the pressure or vacuum its table gives, which the curve then maps to the target.
  bool from_table = false;
  double table_kpa = 0;
};

/// Maps one request for one finger. `finger` comes from HelloReply.
Mapped MapRequest(const protocol::FingerSummary& finger, const LevelTables& levels,
                  const FingerCurves& curves, Request request,
                  RangePolicy policy = RangePolicy::kRefuse);

/// A pneumatic finger's deformation (mm) at a pressure (kPa) through its curve — the calibrated
/// one when loaded, within its range — as a level's table pressure is mapped (scenes map a
/// fingertip stress to pressure, then through this).
double DeformationAtPressure(const FingerCurves& curves, double kpa);
/// A jamming finger's stiffness (N/mm) at a vacuum (kPa, negative) through its curve, likewise.
double StiffnessAtVacuum(const FingerCurves& curves, double vacuum_kpa);

/// The pressure a line is at, as far as the host knows: its sensor's reading, or its setpoint
/// where it has no sensor.
double LinePressurePa(const protocol::LineSummary& line, const protocol::LineSample& sample);

/// Each finger's output — deformation in mm (pneumatic), stiffness in N/mm (jamming) — estimated
/// from one tick's line samples (`tick`: line_count of them, in line order) through the finger's
/// curve. A static estimate: the hysteresis the board's compensator works against is not in it.
std::vector<double> EstimateFingerOutputs(const protocol::HelloReply& board,
                                          const std::vector<FingerCurves>& curves,
                                          const protocol::LineSample* tick);

/// "mm" or "N/mm": the unit a finger's output is in.
const char* OutputUnitName(protocol::FingerKind kind);

}  // namespace palpa::host
