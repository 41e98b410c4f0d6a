// One calibration run's state and phases, shared by its two halves: the measurements on the rig
// (calibration_run.cc) and the fits, the file and the failure detectors (calibration_results.cc).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/quality_checks.h"

namespace palpa::calibration::run_internal {

using nlohmann::json;

/// One run: what the phases share, and the phases in the order they run.
class Run {
 public:
  Run(Rig& rig, uint8_t finger, const ProtocolOptions& o, const RunInfo& info, Journal& journal,
      const std::function<void(const Progress&)>& progress, CalibrationRun* out)
      : rig_(rig),
        finger_(finger),
        o_(o),
        info_(info),
        journal_(journal),
        progress_(progress),
        out_(out),
        jamming_(rig.board.jamming(finger)),
        adaptive_(o.map_protocol == MapProtocol::kAdaptive),
        st_(journal.state),
        drives_(SweepDrives(jamming_ ? o.jamming_sweep : o.pneumatic_sweep)),
        started_(rig.time.Now()),
        earlier_(st_.value("rig_time_s", 0.0)) {
    const int grid_points = !jamming_ ? 0
                            : adaptive_
                                ? o.adaptive.max_cycles
                                : static_cast<int>(o.biases_kpa.size() * o.vacuums_kpa.size());
    p_ = Progress{0, 2 + grid_points + static_cast<int>(drives_.size()), ""};
    // Columns per phase (docs/calibration.md), in the calibration file's units: correction: line,
    // command, rising, falling (Pa); grid: bias, vacuum (Pa), stiffness mean, spread (mN/mm), loop
    // area (mJ); sweep: commanded and measured drive (Pa), output (µm or mN/mm); chamber: line,
    // dead time, regulator and chamber lags (s), fit residual (a fraction of the step).
    out_->csv = {"phase,v1,v2,v3,v4,v5"};
  }

  RigStatus Zero();
  RigStatus Corrections();
  RigStatus Chamber();
  RigStatus Map();
  RigStatus Sweep();
  void Fits();
  RigStatus Detectors();

 private:
  /// Before a step that finds a surface by the contact threshold: the zero read clear of
  /// everything; past the threshold the run stops, force_zero failing in the file's quality.
  RigStatus ZeroStillClear();
  /// What the detectors judge, from what the run has measured so far.
  CheckInputs Inputs() const;
  void Step(const std::string& what) {
    p_.step = what;
    if (progress_) progress_(p_);
  }
  void Done() {
    ++p_.done;
    st_["rig_time_s"] = earlier_ + rig_.time.Now() - started_;
    if (journal_.save) journal_.save(journal_);
    if (progress_) progress_(p_);
  }

  Rig& rig_;
  const uint8_t finger_;
  const ProtocolOptions& o_;
  const RunInfo& info_;
  Journal& journal_;
  const std::function<void(const Progress&)>& progress_;
  CalibrationRun* out_;
  const bool jamming_, adaptive_;
  json& st_;
  const std::vector<double> drives_;  // Pa
  const double started_, earlier_;
  Progress p_;
  double zero_ = 0, tare_noise_ = 0;
  std::vector<double> free_;  // readings clear of everything: before the chamber step, at the end
  std::vector<host::RegulatorCorrection> corrections_;
  std::optional<host::ChamberModel> chamber_;
  double bias_ = 0;
  std::vector<ConditionSummary> grid_;
  std::vector<SweepSample> sweep_;
  bool fitted_ = false;
  std::string inverse_error_;
};

}  // namespace palpa::calibration::run_internal
