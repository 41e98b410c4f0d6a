// A finger's calibration end to end: zero, the regulator's static correction, then (pneumatic) a
// deformation sweep with nested reversals or (jamming) the stiffness map over bias × vacuum —
// the thesis's grid or the adaptive protocol — the recommended bias, and a stiffness sweep at it;
// fits, static inverse, compensator, the failure detectors' verdicts — a calibration file and its
// raw data. Each finished step is kept in a journal, so an interrupted run resumes where it
// stopped.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/calibration/hysteresis_fit.h"
#include "palpa/calibration/map_protocols.h"
#include "palpa/calibration/procedures.h"
#include "palpa/calibration/sweep.h"
#include "palpa/host/calibration_file.h"

namespace palpa::calibration {

/// How a jamming finger's stiffness map is taken (pneumatic fingers have no map: both the same).
enum class MapProtocol { kThesisGrid, kAdaptive };

struct ProtocolOptions {
  MapProtocol map_protocol = MapProtocol::kThesisGrid;
  AdaptiveOptions adaptive{};
  double dwell_s = 3;  ///< settling at each drive before reading
  ContactOptions contact{};
  double press_depth_mm = 3;      ///< thesis: 3 mm
  double press_speed_mm_s = 0.1;  ///< thesis: 0.1 mm/s (the grid, where loop areas are taken)
  /// The stiffness sweep's presses measure the slope only, so they go faster: the whole sweep then
  /// holds vacuum for minutes, inside the board's pump run-time limit (10 min by default).
  double sweep_press_speed_mm_s = 1.0;
  int repeats = 8;  ///< thesis: 8 per condition
  std::vector<double> biases_kpa = {0, 10, 20};
  std::vector<double> vacuums_kpa = {0, -50, -100};
  SweepPlan pneumatic_sweep{100000, 5000, 4};
  SweepPlan jamming_sweep{100000, 10000, 2};
  int correction_points = 8;
  /// The compensator fitted to the sweep, pi or api (both models' residuals are in the finger's
  /// output unit, as the calibration file reports them); empty: the better of the two on this
  /// sweep (FitBetterPlayModel).
  std::optional<protocol::CompensatorKind> compensator;
  /// Its operators; 0: `default_operators`, or fewer when the sweep's steps tell fewer apart (so
  /// every operator adds a degree of freedom; OperatorsToldApart).
  int compensator_operators = 0;
  int default_operators = 16;
};

/// Short settings for demonstrations and tests: fewer and faster points, two repeats.
ProtocolOptions QuickProtocol();

/// The hysteresis sweep a finger gets under these options, and what can be fitted to it.
struct SweepCapacity {
  SweepPlan plan;
  size_t points = 0;      ///< settled readings
  int pi_operators = 0;   ///< the most a pi fit may have for that many readings
  int api_operators = 0;  ///< the same for api
  int told_apart = 0;     ///< the most operators its steps tell apart (up to 32)
  int operators = 0;      ///< what the run fits: the option, or its default capped as above
  /// "28 readings in 20 kPa steps (pi up to 12 operators, api up to 8; its steps tell 10
  /// apart): fitting pi(8) and api(8), keeping the better" — `kind` empty: auto.
  std::string Describe(std::optional<protocol::CompensatorKind> kind) const;
  /// Why `kind` (empty: auto, pi or api) with `operators` cannot be fitted; empty when it can.
  std::string Refusal(std::optional<protocol::CompensatorKind> kind) const;
};
SweepCapacity SweepFor(const ProtocolOptions& options, bool jamming);

/// What a run records as it goes; saved by the caller after every step (resume reads it back).
struct Journal {
  nlohmann::json state = nlohmann::json::object();
  std::function<void(const Journal&)> save;  ///< called after every finished step
};

/// A journal holds a few hundred presses at most: a few hundred KiB.
inline constexpr host::FileLimits kJournalLimits{"calibration journal", 16 * 1024 * 1024};

/// A journal's state as a stopped run left it, every field the protocol reads back checked (a
/// damaged journal is refused naming the field, e.g. "sweep[3][0]: must be a number", before
/// anything moves: an invalid argument). LoadJournal reads the file within kJournalLimits and
/// names it in the error.
host::Result<nlohmann::json> ParseJournal(const std::string& text);
host::Result<nlohmann::json> LoadJournal(const std::string& path);

struct Progress {
  int done = 0, total = 0;
  std::string step;
};

struct RunInfo {
  std::string actuator_serial;
  uint32_t board_id = 0;
  std::string date;  ///< UTC ISO 8601
  std::string rig;
  std::string raw_data;                             ///< CSV file name beside the calibration
  const host::CalibrationFile* previous = nullptr;  ///< the actuator's last calibration, if any
  std::optional<host::SimulatedPlant> simulation =
      std::nullopt;  ///< on palpa-sim's rig: which plant
};

struct CalibrationRun {
  host::CalibrationFile file;
  std::vector<std::string> csv;     ///< raw readings, first line the header
  std::vector<MapPress> map;        ///< jamming: every press of the stiffness map
  std::vector<PressCycle> presses;  ///< the force-depth readings of those taken in this session
  MapEstimate map_estimate;
  std::vector<SweepSample> sweep;
  std::string compensator_choice;  ///< when the protocol chose the model: what it compared
  /// The compensator's fit (its operators and those carrying weight); error set when the model
  /// asked for could not be fitted — the file then carries the static inverse alone.
  HysteresisFit fit;
};

/// Runs (or resumes) the protocol; on a safety stop returns its reason with everything safe,
/// and the journal keeps what was finished.
RigStatus RunCalibration(Rig& rig, uint8_t finger, const ProtocolOptions& options,
                         const RunInfo& info, Journal& journal,
                         const std::function<void(const Progress&)>& progress, CalibrationRun* out);

}  // namespace palpa::calibration
