// RunCalibration in its phases: zero, regulator correction, stiffness map (jamming), hysteresis
// sweep, fits and file, failure detectors — each journalled so a stopped run resumes.
#include <algorithm>
#include <cstdio>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/quality_checks.h"

namespace palpa::calibration {
namespace {

using nlohmann::json;

std::string Csv(const std::vector<double>& v, const std::string& phase) {
  std::string row = phase;
  for (double x : v) {
    char b[32];
    std::snprintf(b, sizeof(b), ",%.6g", x);
    row += b;
  }
  return row;
}

json SamplesJson(const std::vector<SweepSample>& s) {
  json j = json::array();
  for (const SweepSample& p : s) j.push_back({p.drive_pa, p.output});
  return j;
}

std::vector<SweepSample> SamplesFrom(const json& j) {
  std::vector<SweepSample> s;
  for (const json& p : j) s.push_back({p[0].get<double>(), p[1].get<double>()});
  return s;
}

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
    // area (mJ); sweep: commanded and measured drive (Pa), output (µm or mN/mm).
    out_->csv = {"phase,v1,v2,v3,v4,v5"};
  }

  RigStatus Zero();
  RigStatus Corrections();
  RigStatus Map();
  RigStatus Sweep();
  void Fits();
  RigStatus Detectors();

 private:
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
  double zero_ = 0, tare_noise_ = 0, end_free_ = 0;
  std::vector<host::RegulatorCorrection> corrections_;
  double bias_ = 0;
  std::vector<ConditionSummary> grid_;
  std::vector<SweepSample> sweep_;
  bool fitted_ = false;
  std::string inverse_error_;
};

/// 1. Zero (every run, also a resumed one: the rig may have been moved).
RigStatus Run::Zero() {
  Step("zero on the vented surface");
  const RigStatus s = ZeroOnVentedSurface(rig_, finger_, o_.contact, &zero_, &tare_noise_);
  if (s.ok()) Done();
  return s;
}

/// 2. Regulator static correction of each of the finger's lines (bias and vacuum on a jamming
///    finger): the feed-forward map of every pressure loop it uses.
RigStatus Run::Corrections() {
  std::vector<uint8_t> lines = {rig_.board.driven_line(finger_)};
  if (jamming_) lines.insert(lines.begin(), rig_.board.bias_line(finger_));
  if (!st_.contains("corrections")) st_["corrections"] = json::object();
  for (uint8_t line : lines) {
    const std::string key = std::to_string(line);
    if (st_["corrections"].contains(key)) continue;
    Step("regulator static correction, line " + std::to_string(line + 1));
    std::vector<protocol::CorrectionPoint> points;
    const RigStatus s =
        RegulatorCorrection(rig_, finger_, line, o_.correction_points, o_.dwell_s, &points);
    if (!s.ok()) return s;
    json c = json::array();
    for (const auto& q : points) c.push_back({q.command_pa, q.rising_pa, q.falling_pa});
    st_["corrections"][key] = c;
    if (journal_.save) journal_.save(journal_);
  }
  Done();
  for (uint8_t line : lines) {
    host::RegulatorCorrection correction;
    correction.line = line;
    for (const json& q : st_["corrections"][std::to_string(line)]) {
      correction.points.push_back({q[0].get<int32_t>(), q[1].get<int32_t>(), q[2].get<int32_t>()});
      out_->csv.push_back(Csv({static_cast<double>(line + 1), q[0].get<double>(),
                               q[1].get<double>(), q[2].get<double>(), 0},
                              "correction"));
    }
    corrections_.push_back(correction);
  }
  return {};
}

/// 3. Jamming: the stiffness map (the thesis's grid, or adaptive) and the recommended bias.
RigStatus Run::Map() {
  bias_ = o_.biases_kpa.empty() ? 20 : o_.biases_kpa.back();
  if (!jamming_) return {};
  const PressSettings press{o_.press_depth_mm, o_.press_speed_mm_s, o_.dwell_s};
  if (!st_.contains("map")) st_["map"] = json::object();
  MapHooks hooks;
  hooks.step = [this](const std::string& what) { Step(what); };
  hooks.done = [this] { Done(); };
  const RigStatus s = adaptive_
                          ? RunAdaptiveMap(rig_, finger_, zero_, press, o_.adaptive, st_["map"],
                                           hooks, &out_->map, &out_->map_estimate, &out_->presses)
                          : RunGridMap(rig_, finger_, zero_, press, o_.biases_kpa, o_.vacuums_kpa,
                                       o_.repeats, st_["map"], hooks, &out_->map, &out_->presses);
  if (!s.ok()) return s;
  if (!adaptive_) out_->map_estimate = EstimateMap(out_->map, o_.adaptive.box);  // adaptive: own
  grid_ = SummariseConditions(out_->map);
  for (const ConditionSummary& c : grid_) {
    const host::GridPoint g = FileGridPoint(c);
    out_->csv.push_back(Csv(
        {g.bias_pa, g.vacuum_pa, g.stiffness_mean, g.stiffness_spread, g.loop_area_mean}, "grid"));
  }
  bias_ = adaptive_ ? RecommendBiasFromMap(out_->map, o_.adaptive.box) : RecommendBias(grid_);
  return {};
}

/// 4. The hysteresis sweep: deformation by contact detection, or stiffness by one press per
///    point; then the stage retracted and the force zero read again, clear of everything.
RigStatus Run::Sweep() {
  if (!st_.contains("sweep")) st_["sweep"] = json::array();
  sweep_ = SamplesFrom(st_["sweep"]);
  p_.done += static_cast<int>(sweep_.size());
  RigStatus s;
  for (size_t k = sweep_.size(); k < drives_.size(); ++k) {
    const double kpa = drives_[k] / 1000;
    Step("hysteresis sweep " + std::to_string(k + 1) + "/" + std::to_string(drives_.size()));
    std::vector<SweepSample> one;
    if (jamming_) {
      s = rig_.board.SetDrive(finger_, bias_, -kpa);
      if (!s.ok()) return AbortSafe(rig_, s.status, "board: " + s.message);
      rig_.time.Wait(o_.dwell_s);
      PressCycle cycle;
      s = Press(rig_, zero_, o_.press_depth_mm, o_.sweep_press_speed_mm_s, &cycle);
      if (!s.ok()) return s;
      double measured = 0;
      rig_.board.MeasuredKpa(rig_.board.driven_line(finger_), &measured);
      one.push_back({-measured * 1000, cycle.stiffness_n_per_mm * 1000});
    } else {
      s = DeformationSweep(rig_, finger_, {kpa}, o_.dwell_s, zero_, o_.contact, &one);
      if (!s.ok()) return s;
    }
    sweep_.push_back(one.front());
    st_["sweep"] = SamplesJson(sweep_);
    Done();
  }
  rig_.board.SetDrive(finger_, 0, 0);
  s = GuardedMove(rig_, rig_.limits.retract_mm, 2.0);
  if (s.ok()) s = ReadForceMean(rig_, 10, &end_free_);  // clear of everything: the end's zero
  if (!s.ok()) return s;
  for (size_t k = 0; k < sweep_.size(); ++k) {
    out_->csv.push_back(Csv({drives_[k], sweep_[k].drive_pa, sweep_[k].output, 0, 0}, "sweep"));
  }
  out_->sweep = sweep_;
  return {};
}

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

/// 6. The failure detectors; a static inverse that could not be fitted ends the run here.
RigStatus Run::Detectors() {
  host::CalibrationFile& f = out_->file;
  CheckInputs in;
  in.jamming = jamming_;
  in.force_noise_class_n = rig_.force_noise_n;
  in.tare_noise_n = tare_noise_;
  in.map = out_->map;
  in.free_readings = {end_free_};
  in.sweep_points = static_cast<int>(sweep_.size());
  in.corrections = corrections_;
  in.box = o_.adaptive.box;
  in.previous = info_.previous;
  f.quality.checks = RunQualityChecks(in, f);
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

}  // namespace

RigStatus RunCalibration(Rig& rig, uint8_t finger, const ProtocolOptions& o, const RunInfo& info,
                         Journal& journal, const std::function<void(const Progress&)>& progress,
                         CalibrationRun* out) {
  Run run(rig, finger, o, info, journal, progress, out);
  for (RigStatus (Run::*phase)() : {&Run::Zero, &Run::Corrections, &Run::Map, &Run::Sweep}) {
    if (RigStatus s = (run.*phase)(); !s.ok()) return s;
  }
  run.Fits();
  return run.Detectors();
}

}  // namespace palpa::calibration
