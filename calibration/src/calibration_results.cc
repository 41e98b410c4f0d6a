// A calibration run's results from what it measured: the static inverse, the deformation
// branches and the compensator fitted, the calibration file filled in, the failure detectors run
// (force_zero also before a step that needs the zero, where a walked one stops the run).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calibration_run.h"
#include "palpa/calibration/quality_checks.h"

namespace palpa::calibration::run_internal {
namespace {

/// Straight lines through the major rising and falling passes over 10–90 % of the range (the
/// Table 5-4 comparison), in µm against Pa (µm/Pa is the thesis's mm/kPa).
void BranchFits(const std::vector<SweepSample>& sweep, double drive_max, host::CalibrationFile& f) {
  size_t top = 0;
  for (size_t k = 0; k < sweep.size(); ++k) {
    if (sweep[k].drive_pa > sweep[top].drive_pa) top = k;
  }
  std::vector<std::pair<double, double>> up, down;
  for (size_t k = 0; k <= top; ++k) {
    if (sweep[k].drive_pa >= 0.1 * drive_max && sweep[k].drive_pa <= 0.9 * drive_max) {
      up.push_back({sweep[k].drive_pa, sweep[k].output});
    }
  }
  for (size_t k = top; k < sweep.size() && (k == top || sweep[k].drive_pa <= sweep[k - 1].drive_pa);
       ++k) {
    if (sweep[k].drive_pa >= 0.1 * drive_max && sweep[k].drive_pa <= 0.9 * drive_max) {
      down.push_back({sweep[k].drive_pa, sweep[k].output});
    }
  }
  const Line r = FitLine(up), d = FitLine(down);
  f.rising_fit = host::LineFit{r.slope, r.intercept, std::clamp(r.r2, 0.0, 1.0)};
  f.falling_fit = host::LineFit{d.slope, d.intercept, std::clamp(d.r2, 0.0, 1.0)};
}

}  // namespace

/// 5. Fits and the calibration file.
void Run::Fits() {
  host::CalibrationFile& f = out_->file;
  f.actuator_serial = info_.actuator_serial;
  f.kind = jamming_ ? protocol::FingerKind::kJamming : protocol::FingerKind::kPneumatic;
  f.board_id = info_.board_id;
  f.finger = finger_;
  f.date = info_.date;
  f.rig = info_.rig;
  f.simulation = info_.simulation;
  f.speed_um_s = 1000 * (jamming_ ? o_.press_speed_mm_s : o_.contact.speed_mm_s);
  f.depth_um = jamming_ ? 1000 * o_.press_depth_mm : 0;
  f.repeats = jamming_ ? o_.repeats : 1;
  if (jamming_) f.bias_pa = 1000 * bias_;
  f.raw_data = info_.raw_data;
  for (const ConditionSummary& c : grid_) f.grid.push_back(FileGridPoint(c));
  f.regulator_corrections = corrections_;
  if (chamber_) f.chamber_models = {*chamber_};
  const double drive_max = jamming_ ? o_.jamming_sweep.drive_max : o_.pneumatic_sweep.drive_max;
  const int inverse_points = static_cast<int>(std::clamp<size_t>(sweep_.size() / 2, 2, 12));
  const auto inverse = FitStaticInverse(sweep_, inverse_points, jamming_);
  inverse_error_ = inverse.message;
  f.static_inverse = inverse.value;
  fitted_ = f.static_inverse.size() >= 2;  // if not, the detectors still say why
  for (const protocol::InversePoint& q : f.static_inverse) {
    f.curve.push_back({static_cast<double>(q.setpoint_pa), static_cast<double>(q.output)});
  }
  if (!jamming_ && fitted_) BranchFits(sweep_, drive_max, f);
  HysteresisFit& fit = out_->fit;
  const int operators = SweepFor(o_, jamming_).operators;
  if (!o_.compensator) {
    fit = FitBetterPlayModel(sweep_, operators, drive_max, &out_->compensator_choice);
  } else {
    fit = FitCompensator(*o_.compensator, operators, sweep_, drive_max);
    const bool play = *o_.compensator == protocol::CompensatorKind::kPrandtlIshlinskii ||
                      *o_.compensator == protocol::CompensatorKind::kAsymmetricPi;
    if (!play) fit.error = "a calibration fits pi or api";  // their residuals are output units
  }
  if (fit.ok()) {
    f.compensator = fit.kind;
    f.compensator_params = fit.params;
    f.quality.residual_rms = fit.residual_rms;  // in the sweep's output unit, as the curve
    f.quality.residual_max = fit.residual_max;
  } else {
    f.quality.flags.push_back("compensator not fitted: " + fit.error);
  }
  if (jamming_) f.recommended_bias_pa = 1000 * bias_;
  f.quality.points = static_cast<int>(sweep_.size());
  f.quality.protocol = jamming_ && adaptive_ ? "adaptive" : "thesis";
  f.quality.cycles = static_cast<int>(out_->map.size());
  f.quality.rig_time_s = earlier_ + rig_.time.Now() - started_;
  if (jamming_) f.quality.map_error = out_->map_estimate.map_error;
}

CheckInputs Run::Inputs() const {
  CheckInputs in;
  in.jamming = jamming_;
  in.force_noise_class_n = rig_.force_noise_n;
  in.tare_noise_n = tare_noise_;
  in.map = out_->map;
  in.free_readings = free_;
  in.sweep_points = static_cast<int>(sweep_.size());
  in.corrections = corrections_;
  in.box = o_.adaptive.box;
  in.previous = info_.previous;
  return in;
}

RigStatus Run::ZeroStillClear() {
  double clear = 0;
  bool walked = false;
  const RigStatus s = CheckZeroBefore(rig_, o_.contact, p_.step, &clear, &walked);
  if (!std::isnan(clear)) free_.push_back(clear);
  if (walked) {
    // Stopped by the zero: the file's quality says so as the finished run's detectors would.
    host::CalibrationFile& f = out_->file;
    f.quality.checks = {CheckForceZero(Inputs())};
    if (!f.quality.checks[0].passed)
      f.quality.flags.push_back("force_zero: " + f.quality.checks[0].detail);
  }
  return s;
}

/// 6. The failure detectors; a static inverse that could not be fitted ends the run here.
RigStatus Run::Detectors() {
  host::CalibrationFile& f = out_->file;
  f.quality.checks = RunQualityChecks(Inputs(), f);
  for (const host::QualityCheck& c : f.quality.checks) {
    if (!c.passed) f.quality.flags.push_back(c.name + ": " + c.detail);
  }
  if (jamming_ && adaptive_ && out_->map_estimate.map_error > o_.adaptive.target_error) {
    char why[160];
    std::snprintf(why, sizeof(why),
                  "map: estimated error %.1f %% still above the %.1f %% target after the budget "
                  "of %d cycles",
                  100 * out_->map_estimate.map_error, 100 * o_.adaptive.target_error,
                  o_.adaptive.max_cycles);
    f.quality.flags.push_back(why);
  }
  if (!fitted_) {
    std::string why = "static inverse: " + inverse_error_;
    for (const std::string& flag : f.quality.flags) why += "; " + flag;
    return RigStatus::Fail(Status::kUnavailable, why);
  }
  return {};
}

}  // namespace palpa::calibration::run_internal
