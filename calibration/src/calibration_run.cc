// RunCalibration and its measuring phases: zero, regulator correction, stiffness map (jamming),
// hysteresis sweep — each journalled so a stopped run resumes. The fits, the file and the
// failure detectors that follow are calibration_results.cc.
#include <algorithm>
#include <cstdio>

#include "calibration_run.h"
#include "palpa/calibration/chamber_step.h"

namespace palpa::calibration {
namespace run_internal {
namespace {

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

}  // namespace

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
      // From the last point's surface: from the zero, the indenter would first be driven into
      // the inflated film (4 mm at the top) and back off in steps until clear.
      const double expected = sweep_.empty() ? zero_ : zero_ + sweep_.back().output / 1000;
      s = DeformationSweep(rig_, finger_, {kpa}, o_.dwell_s, zero_, o_.contact, &one, expected);
      if (!s.ok()) return s;
    }
    sweep_.push_back(one.front());
    st_["sweep"] = SamplesJson(sweep_);
    Done();
  }
  rig_.board.SetDrive(finger_, 0, 0);
  s = Chamber();
  double end_free = 0;
  if (s.ok()) s = ReadClearForce(rig_, 2.0, &end_free);  // the end's zero
  if (!s.ok()) return s;
  free_.push_back(end_free);
  for (size_t k = 0; k < sweep_.size(); ++k) {
    out_->csv.push_back(Csv({drives_[k], sweep_[k].drive_pa, sweep_[k].output, 0, 0}, "sweep"));
  }
  out_->sweep = sweep_;
  return {};
}

/// 4b. The driven line's chamber, once the sweep is done (its pressure history would otherwise be
///     the sweep's): its step response on the rig and the lag fitted to it, which the board
///     shapes that line's steps with. None identified is no failure: the line is not shaped.
RigStatus Run::Chamber() {
  const uint8_t line = rig_.board.driven_line(finger_);
  if (!st_.contains("chamber")) {
    Step("chamber step response, line " + std::to_string(line + 1));
    RigStatus s = ZeroStillClear();  // its surface search reads contact by the threshold
    if (!s.ok()) return s;
    ChamberStep step;
    s = MeasureChamberStep(rig_, finger_, zero_, o_.contact, ChamberStepFor(jamming_), &step);
    if (!s.ok()) return s;
    st_["chamber"] = json::array();
    if (step.fit.ok) {
      st_["chamber"].push_back({step.fit.dead_time_s, step.fit.regulator_tau_s, step.fit.tau_s,
                                step.fit.rms, step.fit.outlet_tau_s, step.fit.outlet_rms});
    }
    if (journal_.save) journal_.save(journal_);
  }
  for (const json& c : st_["chamber"]) {
    host::ChamberModel m;
    m.line = line;
    m.dead_time_s = c[0].get<double>();
    m.regulator_tau_s = c[1].get<double>();
    m.chamber_tau_s = std::max(1e-6, c[2].get<double>());
    m.fit_rms = c[3].get<double>();
    // The tube's lag behind the outlet, the board's (0 where the outlet was not read: the line
    // is not shaped).
    m.tube_tau_s = c[4].get<double>();
    m.tube_fit_rms = c[5].get<double>();
    chamber_ = m;
    out_->csv.push_back(Csv({static_cast<double>(line + 1), m.dead_time_s, m.regulator_tau_s,
                             m.chamber_tau_s, m.fit_rms},
                            "chamber"));
    out_->csv.push_back(
        Csv({static_cast<double>(line + 1), m.tube_tau_s, m.tube_fit_rms, 0, 0}, "chamber-tube"));
  }
  return {};
}

}  // namespace run_internal

RigStatus RunCalibration(Rig& rig, uint8_t finger, const ProtocolOptions& o, const RunInfo& info,
                         Journal& journal, const std::function<void(const Progress&)>& progress,
                         CalibrationRun* out) {
  run_internal::Run run(rig, finger, o, info, journal, progress, out);
  using run_internal::Run;
  for (RigStatus (Run::*phase)() : {&Run::Zero, &Run::Corrections, &Run::Map, &Run::Sweep}) {
    if (RigStatus s = (run.*phase)(); !s.ok()) return s;
  }
  run.Fits();
  return run.Detectors();
}

}  // namespace palpa::calibration
