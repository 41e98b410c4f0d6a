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
  /// The compensator fitted to the sweep, pi or api, with this many operators (both models'
  /// residuals are in the finger's output unit, as the calibration file reports them); empty:
  /// the better of the two on this sweep (FitBetterPlayModel).
  std::optional<protocol::CompensatorKind> compensator;
  int compensator_operators = 16;
};

/// Short settings for demonstrations and tests: fewer and faster points, two repeats.
ProtocolOptions QuickProtocol();

/// What a run records as it goes; saved by the caller after every step (resume reads it back).
struct Journal {
  nlohmann::json state = nlohmann::json::object();
  std::function<void(const Journal&)> save;  ///< called after every finished step
};

/// A journal holds a few hundred presses at most: a few hundred KiB.
inline constexpr host::FileLimits kJournalLimits{"calibration journal", 16 * 1024 * 1024};

/// A journal's state as a stopped run left it, every field the protocol reads back checked (a
/// damaged journal is refused naming the field, e.g. "sweep[3][0]: must be a number", before
/// anything moves); nullopt with *error otherwise. LoadJournal reads the file within
/// kJournalLimits and names it in the error.
std::optional<nlohmann::json> ParseJournal(const std::string& text, std::string* error);
std::optional<nlohmann::json> LoadJournal(const std::string& path, std::string* error);

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
};

struct CalibrationRun {
  host::CalibrationFile file;
  std::vector<std::string> csv;     ///< raw readings, first line the header
  std::vector<MapPress> map;        ///< jamming: every press of the stiffness map
  std::vector<PressCycle> presses;  ///< the force-depth readings of those taken in this session
  MapEstimate map_estimate;
  std::vector<SweepSample> sweep;
  std::string compensator_choice;  ///< when the protocol chose the model: what it compared
};

/// Runs (or resumes) the protocol; on a safety stop returns its reason with everything safe,
/// and the journal keeps what was finished.
RigStatus RunCalibration(Rig& rig, uint8_t finger, const ProtocolOptions& options,
                         const RunInfo& info, Journal& journal,
                         const std::function<void(const Progress&)>& progress, CalibrationRun* out);

}  // namespace palpa::calibration
