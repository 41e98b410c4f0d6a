// The thesis protocol, step by step, with a journal for resuming.
#include "palpa/calibration/calibration_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "palpa/calibration/play_operators.h"
#include "palpa/calibration/quality_checks.h"
#include "palpa/core/compensator.h"

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

}  // namespace

ProtocolOptions QuickProtocol() {
  ProtocolOptions o;
  o.dwell_s = 0.5;
  o.contact.speed_mm_s = 1.0;
  o.press_depth_mm = 2;
  o.press_speed_mm_s = 2;
  o.sweep_press_speed_mm_s = 2;
  o.repeats = 2;
  o.biases_kpa = {0, 20};
  o.vacuums_kpa = {0, -100};
  // 10 kPa steps: 53 and 39 readings where api(8) needs 28 and pi(8) 20, so the fit has readings
  // to spare (at 20 kPa api(8) had exactly its 28 and followed the sweep's noise).
  o.pneumatic_sweep = SweepPlan{100000, 10000, 2};
  o.jamming_sweep = SweepPlan{100000, 10000, 1};
  o.correction_points = 4;
  o.default_operators = 8;
  return o;
}

SweepCapacity SweepFor(const ProtocolOptions& o, bool jamming) {
  SweepCapacity c;
  c.plan = jamming ? o.jamming_sweep : o.pneumatic_sweep;
  const std::vector<double> drives = SweepDrives(c.plan);
  c.points = drives.size();
  c.pi_operators = MaxOperators(protocol::CompensatorKind::kPrandtlIshlinskii, c.points);
  c.api_operators = MaxOperators(protocol::CompensatorKind::kAsymmetricPi, c.points);
  c.told_apart = OperatorsToldApart(drives, c.plan.drive_max, core::kMaxPlayOperators);
  c.operators = o.compensator_operators > 0
                    ? o.compensator_operators
                    : std::max(1, std::min(o.default_operators, c.told_apart));
  return c;
}

std::string SweepCapacity::Describe(std::optional<protocol::CompensatorKind> kind) const {
  const std::string n = "(" + std::to_string(operators) + ")";
  std::string fitting = !kind ? "pi" + n + " and api" + n + ", keeping the better"
                        : *kind == protocol::CompensatorKind::kAsymmetricPi ? "api" + n
                                                                            : "pi" + n;
  if (operators > told_apart) {
    fitting += " (its steps tell only " + std::to_string(told_apart) + " operators apart)";
  }
  char text[160];
  std::snprintf(text, sizeof(text),
                "%zu readings in %g kPa steps (pi up to %d operators, api up to %d; its steps tell "
                "%d apart): fitting ",
                points, plan.step / 1000, pi_operators, api_operators, told_apart);
  return text + fitting;
}

std::string SweepCapacity::Refusal(std::optional<protocol::CompensatorKind> kind) const {
  using protocol::CompensatorKind;
  const std::string n = "(" + std::to_string(operators) + ")";
  auto too_short = [&](CompensatorKind k, const std::string& name, int most) {
    return name + n + " needs " + std::to_string(MinSweepPoints(k, operators)) +
           " sweep readings; this sweep has " + std::to_string(points) + " (" + name + " up to " +
           std::to_string(most) + ")";
  };
  const bool pi = operators <= pi_operators, api = operators <= api_operators;
  if (kind == CompensatorKind::kPrandtlIshlinskii && !pi)
    return too_short(*kind, "pi", pi_operators);
  if (kind == CompensatorKind::kAsymmetricPi && !api) return too_short(*kind, "api", api_operators);
  if (!kind && !pi && !api) {
    return "neither pi" + n + " nor api" + n + ": " +
           too_short(CompensatorKind::kPrandtlIshlinskii, "pi", pi_operators);
  }
  return {};
}

RigStatus RunCalibration(Rig& rig, uint8_t finger, const ProtocolOptions& o, const RunInfo& info,
                         Journal& journal, const std::function<void(const Progress&)>& progress,
                         CalibrationRun* out) {
  const bool jamming = rig.board.jamming(finger);
  json& st = journal.state;
  const std::vector<double> drives =
      SweepDrives(jamming ? o.jamming_sweep : o.pneumatic_sweep);  // Pa
  const bool adaptive = o.map_protocol == MapProtocol::kAdaptive;
  const int grid_points = !jamming   ? 0
                          : adaptive ? o.adaptive.max_cycles
                                     : static_cast<int>(o.biases_kpa.size() * o.vacuums_kpa.size());
  const double started = rig.time.Now(), earlier = st.value("rig_time_s", 0.0);
  Progress p{0, 2 + grid_points + static_cast<int>(drives.size()), ""};
  auto step = [&](const std::string& what) {
    p.step = what;
    if (progress) progress(p);
  };
  auto done = [&] {
    ++p.done;
    st["rig_time_s"] = earlier + rig.time.Now() - started;
    if (journal.save) journal.save(journal);
    if (progress) progress(p);
  };
  // Columns per phase (docs/calibration.md), in the calibration file's units: correction: line,
  // command, rising, falling (Pa); grid: bias, vacuum (Pa), stiffness mean, spread (mN/mm), loop
  // area (mJ); sweep: commanded and measured drive (Pa), output (µm or mN/mm).
  out->csv = {"phase,v1,v2,v3,v4,v5"};

  // 1. Zero (every run, also a resumed one: the rig may have been moved).
  step("zero on the vented surface");
  double zero = 0, tare_noise = 0;
  RigStatus s = ZeroOnVentedSurface(rig, finger, o.contact, &zero, &tare_noise);
  if (!s.ok) return s;
  done();

  // 2. Regulator static correction of each of the finger's lines (bias and vacuum on a jamming
  //    finger): the feed-forward map of every pressure loop it uses.
  std::vector<uint8_t> lines = {rig.board.driven_line(finger)};
  if (jamming) lines.insert(lines.begin(), rig.board.bias_line(finger));
  if (!st.contains("corrections")) st["corrections"] = json::object();
  for (uint8_t line : lines) {
    const std::string key = std::to_string(line);
    if (!st["corrections"].contains(key)) {
      step("regulator static correction, line " + std::to_string(line + 1));
      std::vector<protocol::CorrectionPoint> points;
      s = RegulatorCorrection(rig, finger, line, o.correction_points, o.dwell_s, &points);
      if (!s.ok) return s;
      json c = json::array();
      for (const auto& q : points) c.push_back({q.command_pa, q.rising_pa, q.falling_pa});
      st["corrections"][key] = c;
      if (journal.save) journal.save(journal);
    }
  }
  done();
  std::vector<host::RegulatorCorrection> corrections;
  for (uint8_t line : lines) {
    host::RegulatorCorrection correction;
    correction.line = line;
    for (const json& q : st["corrections"][std::to_string(line)]) {
      correction.points.push_back({q[0].get<int32_t>(), q[1].get<int32_t>(), q[2].get<int32_t>()});
      out->csv.push_back(Csv({static_cast<double>(line + 1), q[0].get<double>(), q[1].get<double>(),
                              q[2].get<double>(), 0},
                             "correction"));
    }
    corrections.push_back(correction);
  }

  // 3. Jamming: the stiffness map (the thesis's grid, or adaptive) and the recommended bias.
  double bias = o.biases_kpa.empty() ? 20 : o.biases_kpa.back();
  std::vector<ConditionSummary> grid;
  if (jamming) {
    const PressSettings press{o.press_depth_mm, o.press_speed_mm_s, o.dwell_s};
    if (!st.contains("map")) st["map"] = json::object();
    MapHooks hooks;
    hooks.step = step;
    hooks.done = done;
    s = adaptive ? RunAdaptiveMap(rig, finger, zero, press, o.adaptive, st["map"], hooks, &out->map,
                                  &out->map_estimate, &out->presses)
                 : RunGridMap(rig, finger, zero, press, o.biases_kpa, o.vacuums_kpa, o.repeats,
                              st["map"], hooks, &out->map, &out->presses);
    if (!s.ok) return s;
    if (!adaptive) out->map_estimate = EstimateMap(out->map, o.adaptive.box);  // adaptive: its own
    grid = SummariseConditions(out->map);
    for (const ConditionSummary& c : grid) {
      const host::GridPoint g = FileGridPoint(c);
      out->csv.push_back(
          Csv({g.bias_pa, g.vacuum_pa, g.stiffness_mean, g.stiffness_spread, g.loop_area_mean},
              "grid"));
    }
    bias = adaptive ? RecommendBiasFromMap(out->map, o.adaptive.box) : RecommendBias(grid);
  }

  // 4. The hysteresis sweep: deformation by contact detection, or stiffness by one press per point.
  if (!st.contains("sweep")) st["sweep"] = json::array();
  std::vector<SweepSample> sweep = SamplesFrom(st["sweep"]);
  p.done += static_cast<int>(sweep.size());
  for (size_t k = sweep.size(); k < drives.size(); ++k) {
    const double kpa = drives[k] / 1000;
    step("hysteresis sweep " + std::to_string(k + 1) + "/" + std::to_string(drives.size()));
    std::vector<SweepSample> one;
    if (jamming) {
      s = rig.board.SetDrive(finger, bias, -kpa);
      if (!s.ok) return AbortSafe(rig, "board: " + s.error);
      rig.time.Wait(o.dwell_s);
      PressCycle cycle;
      s = Press(rig, zero, o.press_depth_mm, o.sweep_press_speed_mm_s, &cycle);
      if (!s.ok) return s;
      double measured = 0;
      rig.board.MeasuredKpa(rig.board.driven_line(finger), &measured);
      one.push_back({-measured * 1000, cycle.stiffness_n_per_mm * 1000});
    } else {
      s = DeformationSweep(rig, finger, {kpa}, o.dwell_s, zero, o.contact, &one);
      if (!s.ok) return s;
    }
    sweep.push_back(one.front());
    st["sweep"] = SamplesJson(sweep);
    done();
  }
  rig.board.SetDrive(finger, 0, 0);
  s = GuardedMove(rig, rig.limits.retract_mm, 2.0);
  double end_free = 0;
  if (s.ok) s = ReadForceMean(rig, 10, &end_free);  // clear of everything: the zero at the end
  if (!s.ok) return s;
  for (size_t k = 0; k < sweep.size(); ++k) {
    out->csv.push_back(Csv({drives[k], sweep[k].drive_pa, sweep[k].output, 0, 0}, "sweep"));
  }
  out->sweep = sweep;

  // 5. Fits and the calibration file.
  host::CalibrationFile& f = out->file;
  f.actuator_serial = info.actuator_serial;
  f.kind = jamming ? protocol::FingerKind::kJamming : protocol::FingerKind::kPneumatic;
  f.board_id = info.board_id;
  f.finger = finger;
  f.date = info.date;
  f.rig = info.rig;
  f.simulation = info.simulation;
  f.speed_um_s = 1000 * (jamming ? o.press_speed_mm_s : o.contact.speed_mm_s);
  f.depth_um = jamming ? 1000 * o.press_depth_mm : 0;
  f.repeats = jamming ? o.repeats : 1;
  if (jamming) f.bias_pa = 1000 * bias;
  f.raw_data = info.raw_data;
  for (const ConditionSummary& c : grid) f.grid.push_back(FileGridPoint(c));
  f.regulator_corrections = corrections;
  const double drive_max = jamming ? o.jamming_sweep.drive_max : o.pneumatic_sweep.drive_max;
  std::string error;
  const int inverse_points = static_cast<int>(std::clamp<size_t>(sweep.size() / 2, 2, 12));
  f.static_inverse = FitStaticInverse(sweep, inverse_points, jamming, &error);
  const bool fitted = f.static_inverse.size() >= 2;  // if not, the detectors still say why
  for (const protocol::InversePoint& q : f.static_inverse) {
    f.curve.push_back({static_cast<double>(q.setpoint_pa), static_cast<double>(q.output)});
  }
  if (!jamming && fitted) BranchFits(sweep, drive_max, f);
  HysteresisFit& fit = out->fit;
  const int operators = SweepFor(o, jamming).operators;
  if (!o.compensator) {
    fit = FitBetterPlayModel(sweep, operators, drive_max, &out->compensator_choice);
  } else {
    fit = FitCompensator(*o.compensator, operators, sweep, drive_max);
    const bool play = *o.compensator == protocol::CompensatorKind::kPrandtlIshlinskii ||
                      *o.compensator == protocol::CompensatorKind::kAsymmetricPi;
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
  if (jamming) f.recommended_bias_pa = 1000 * bias;
  f.quality.points = static_cast<int>(sweep.size());
  f.quality.protocol = jamming && adaptive ? "adaptive" : "thesis";
  f.quality.cycles = static_cast<int>(out->map.size());
  f.quality.rig_time_s = earlier + rig.time.Now() - started;
  if (jamming) f.quality.map_error = out->map_estimate.map_error;

  // 6. The failure detectors.
  CheckInputs in;
  in.jamming = jamming;
  in.force_noise_class_n = rig.force_noise_n;
  in.tare_noise_n = tare_noise;
  in.map = out->map;
  in.free_readings = {end_free};
  in.sweep_points = static_cast<int>(sweep.size());
  in.corrections = corrections;
  in.box = o.adaptive.box;
  in.previous = info.previous;
  f.quality.checks = RunQualityChecks(in, f);
  for (const host::QualityCheck& c : f.quality.checks) {
    if (!c.passed) f.quality.flags.push_back(c.name + ": " + c.detail);
  }
  if (jamming && adaptive && out->map_estimate.map_error > o.adaptive.target_error) {
    char why[160];
    std::snprintf(why, sizeof(why),
                  "map: estimated error %.1f %% still above the %.1f %% target after the budget "
                  "of %d cycles",
                  100 * out->map_estimate.map_error, 100 * o.adaptive.target_error,
                  o.adaptive.max_cycles);
    f.quality.flags.push_back(why);
  }
  if (!fitted) {
    std::string why = "static inverse: " + error;
    for (const std::string& flag : f.quality.flags) why += "; " + flag;
    return RigStatus::Fail(why);
  }
  return {};
}

}  // namespace palpa::calibration
