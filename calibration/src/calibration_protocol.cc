// The thesis protocol, step by step, with a journal for resuming.
#include "palpa/calibration/thesis_protocol.h"

#include <algorithm>
#include <cmath>
#include <map>

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

/// Mean and population spread.
std::pair<double, double> MeanSpread(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x / static_cast<double>(v.size());
  for (double x : v) s += (x - m) * (x - m) / static_cast<double>(v.size());
  return {m, std::sqrt(s)};
}

/// Straight lines through the major rising and falling passes over 10–90 % of the range (the
/// Table 5-4 comparison), in mm against kPa.
void BranchFits(const std::vector<SweepSample>& sweep, double drive_max, host::CalibrationFile& f) {
  size_t top = 0;
  for (size_t k = 0; k < sweep.size(); ++k) {
    if (sweep[k].drive_pa > sweep[top].drive_pa) top = k;
  }
  std::vector<std::pair<double, double>> up, down;
  for (size_t k = 0; k <= top; ++k) {
    if (sweep[k].drive_pa >= 0.1 * drive_max && sweep[k].drive_pa <= 0.9 * drive_max) {
      up.push_back({sweep[k].drive_pa / 1000, sweep[k].output / 1000});
    }
  }
  for (size_t k = top; k < sweep.size() && (k == top || sweep[k].drive_pa <= sweep[k - 1].drive_pa);
       ++k) {
    if (sweep[k].drive_pa >= 0.1 * drive_max && sweep[k].drive_pa <= 0.9 * drive_max) {
      down.push_back({sweep[k].drive_pa / 1000, sweep[k].output / 1000});
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
  o.pneumatic_sweep = SweepPlan{100000, 20000, 2};
  o.jamming_sweep = SweepPlan{100000, 20000, 1};
  o.correction_points = 4;
  o.compensator_operators = 8;
  return o;
}

double RecommendBias(const std::vector<host::GridPoint>& grid) {
  // "Kept" allows for what a few presses resolve: a bias may lose a fifth of the widest range.
  constexpr double kRangeKept = 0.8;
  std::map<double, std::pair<double, double>> range;  // bias → (min, max) stiffness
  std::map<double, std::vector<double>> loops;
  for (const host::GridPoint& g : grid) {
    auto& r = range.try_emplace(g.bias_kpa, 1e9, -1e9).first->second;
    r.first = std::min(r.first, g.stiffness_mean);
    r.second = std::max(r.second, g.stiffness_mean);
    loops[g.bias_kpa].push_back(g.loop_area_mean);
  }
  double widest = 0;
  for (const auto& [bias, r] : range) widest = std::max(widest, r.second - r.first);
  double best = range.empty() ? 0 : range.begin()->first, least = 1e300;
  for (const auto& [bias, r] : range) {
    if (r.second - r.first < kRangeKept * widest) continue;
    const double loop = MeanSpread(loops[bias]).first;
    if (loop < least) {
      least = loop;
      best = bias;
    }
  }
  return best;
}

RigStatus RunThesisProtocol(Rig& rig, uint8_t finger, const ProtocolOptions& o, const RunInfo& info,
                            Journal& journal, const std::function<void(const Progress&)>& progress,
                            CalibrationRun* out) {
  const bool jamming = rig.board.jamming(finger);
  json& st = journal.state;
  const std::vector<double> drives =
      SweepDrives(jamming ? o.jamming_sweep : o.pneumatic_sweep);  // Pa
  const int grid_points =
      jamming ? static_cast<int>(o.biases_kpa.size() * o.vacuums_kpa.size()) : 0;
  Progress p{0, 2 + grid_points + static_cast<int>(drives.size()), ""};
  auto step = [&](const std::string& what) {
    p.step = what;
    if (progress) progress(p);
  };
  auto done = [&] {
    ++p.done;
    if (journal.save) journal.save(journal);
    if (progress) progress(p);
  };
  // Columns per phase (docs/calibration.md): correction: line, command, rising, falling (kPa);
  // grid: bias, vacuum (kPa), stiffness mean, spread (N/mm), loop area (mJ); sweep: commanded and
  // measured drive (kPa), output (µm or mN/mm).
  out->csv = {"phase,v1,v2,v3,v4,v5"};

  // 1. Zero (every run, also a resumed one: the rig may have been moved).
  step("zero on the vented surface");
  double zero = 0;
  RigStatus s = ZeroOnVentedSurface(rig, finger, o.contact, &zero);
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
      out->csv.push_back(Csv({static_cast<double>(line + 1), q[0].get<double>() / 1000,
                              q[1].get<double>() / 1000, q[2].get<double>() / 1000, 0},
                             "correction"));
    }
    corrections.push_back(correction);
  }

  // 3. Jamming: the indentation grid and the recommended bias.
  double bias = o.biases_kpa.empty() ? 20 : o.biases_kpa.back();
  std::vector<host::GridPoint> grid;
  if (jamming) {
    if (!st.contains("grid")) st["grid"] = json::array();
    size_t index = 0;
    for (double b : o.biases_kpa) {
      for (double v : o.vacuums_kpa) {
        if (index++ < st["grid"].size()) {
          ++p.done;
          continue;
        }
        step("indentation grid: bias " + std::to_string(static_cast<int>(b)) + " kPa, vacuum " +
             std::to_string(static_cast<int>(v)) + " kPa");
        s = rig.board.SetDrive(finger, b, v);
        if (!s.ok) return AbortSafe(rig, "board: " + s.error);
        rig.time.Wait(o.dwell_s);
        std::vector<double> k, loop, r2;
        for (int r = 0; r < o.repeats; ++r) {
          PressCycle cycle;
          s = Press(rig, zero, o.press_depth_mm, o.press_speed_mm_s, &cycle);
          if (!s.ok) return s;
          k.push_back(cycle.stiffness_n_per_mm);
          loop.push_back(cycle.loop_area_mj);
          r2.push_back(cycle.r2);
          out->presses.push_back(cycle);
        }
        // Vacuum released between points: each condition is approached from rest (the same
        // branch of the vacuum history every time), and the pump rests inside its run-time limit.
        s = rig.board.SetDrive(finger, b, 0);
        if (!s.ok) return AbortSafe(rig, "board: " + s.error);
        rig.time.Wait(o.dwell_s);
        const auto [km, ks] = MeanSpread(k);
        st["grid"].push_back({b, v, o.repeats, km, ks, MeanSpread(loop).first,
                              *std::min_element(r2.begin(), r2.end())});
        done();
      }
    }
    for (const json& g : st["grid"]) {
      grid.push_back(host::GridPoint{g[0].get<double>(), g[1].get<double>(), g[2].get<int>(),
                                     g[3].get<double>(), g[4].get<double>(), g[5].get<double>(),
                                     std::clamp(g[6].get<double>(), 0.0, 1.0)});
      out->csv.push_back(Csv({g[0].get<double>(), g[1].get<double>(), g[3].get<double>(),
                              g[4].get<double>(), g[5].get<double>()},
                             "grid"));
    }
    bias = RecommendBias(grid);
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
  GuardedMove(rig, rig.limits.retract_mm, 2.0);
  for (size_t k = 0; k < sweep.size(); ++k) {
    out->csv.push_back(
        Csv({drives[k] / 1000, sweep[k].drive_pa / 1000, sweep[k].output, 0, 0}, "sweep"));
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
  f.speed_mm_s = jamming ? o.press_speed_mm_s : o.contact.speed_mm_s;
  f.depth_mm = jamming ? o.press_depth_mm : 0;
  f.repeats = jamming ? o.repeats : 1;
  if (jamming) f.bias_kpa = bias;
  f.raw_data = info.raw_data;
  f.grid = grid;
  f.regulator_corrections = corrections;
  const double drive_max = jamming ? o.jamming_sweep.drive_max : o.pneumatic_sweep.drive_max;
  std::string error;
  const int inverse_points = static_cast<int>(std::clamp<size_t>(sweep.size() / 2, 2, 12));
  f.static_inverse = FitStaticInverse(sweep, inverse_points, jamming, &error);
  if (f.static_inverse.size() < 2) return RigStatus::Fail("static inverse: " + error);
  for (const protocol::InversePoint& q : f.static_inverse) {
    f.curve.push_back({q.setpoint_pa / 1000.0, q.output / 1000.0});
  }
  if (!jamming) BranchFits(sweep, drive_max, f);
  const HysteresisFit fit = FitPi(sweep, o.compensator_operators, drive_max);
  if (fit.ok()) {
    f.compensator = fit.kind;
    f.compensator_params = fit.params;
    f.quality.residual_rms = fit.residual_rms / 1000;  // in the curve's unit (mm or N/mm)
    f.quality.residual_max = fit.residual_max / 1000;
  } else {
    f.quality.flags.push_back("compensator not fitted: " + fit.error);
  }
  if (jamming) f.recommended_bias_kpa = bias;
  f.quality.points = static_cast<int>(sweep.size());
  return {};
}

}  // namespace palpa::calibration
