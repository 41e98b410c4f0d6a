// HTML calibration report with inline SVG charts.
#include "palpa/calibration/report.h"

#include <cstdio>
#include <map>
#include <set>

#include "palpa/host/calibration_units.h"
#include "palpa/host/svg_chart.h"

namespace palpa::calibration {
namespace {

using host::Chart;
using host::Series;

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string Fixed(double v, int decimals) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.*f", decimals, v);
  return b;
}

std::string SweepChart(const CalibrationRun& run) {
  const host::CalibrationFile& f = run.file;
  const bool jamming = f.kind == protocol::FingerKind::kJamming;
  Chart c;
  c.title =
      jamming ? "Stiffness sweep at the recommended bias" : "Deformation sweep (contact detection)";
  c.x_label = jamming ? "vacuum (Pa, magnitude)" : "pressure (Pa)";
  c.y_label = jamming ? "stiffness (mN/mm)" : "deformation (µm)";
  Series readings{"readings, in order", {}, "#2471a3", false, false};
  for (const SweepSample& s : run.sweep) readings.points.push_back({s.drive_pa, s.output});
  c.series.push_back(readings);
  Series mid{"calibrated curve (mid-line)", {}, "#c0392b", false, true};
  for (const host::CurvePoint& p : f.curve)
    mid.points.push_back({jamming ? -p.drive_pa : p.drive_pa, p.output});
  c.series.push_back(mid);
  if (f.rising_fit && f.falling_fit) {
    auto line = [](const host::LineFit& l, const char* name, const char* color) {
      return Series{
          name,
          {{10000, l.intercept + 10000 * l.slope}, {90000, l.intercept + 90000 * l.slope}},
          color,
          true,
          false};
    };
    c.series.push_back(line(*f.rising_fit, "rising fit", "#229954"));
    c.series.push_back(line(*f.falling_fit, "falling fit", "#7d3c98"));
    // Table 5-4: 0.0428 mm/kPa (= µm/Pa), -0.2501 mm.
    c.series.push_back(line(host::LineFit{0.0428, -250.1, 1}, "Table 5-4 inflation", "#999"));
  }
  return host::RenderSvg(c);
}

std::string CorrectionChart(const host::RegulatorCorrection& rc) {
  Chart c;
  c.title = "Regulator static correction, line " + std::to_string(rc.line + 1) + " (trim off)";
  c.x_label = "command (Pa)";
  c.y_label = "measured - command (Pa)";
  Series rising{"rising", {}, "#2471a3", false, false},
      falling{"falling", {}, "#c0392b", false, false};
  for (const protocol::CorrectionPoint& p : rc.points) {
    rising.points.push_back({1.0 * p.command_pa, 1.0 * (p.rising_pa - p.command_pa)});
    falling.points.push_back({1.0 * p.command_pa, 1.0 * (p.falling_pa - p.command_pa)});
  }
  c.series = {rising, falling};
  return host::RenderSvg(c);
}

std::string ResidualChart(const CalibrationRun& run) {
  const host::CalibrationFile& f = run.file;
  Chart c;
  c.title = "Compensator fit residuals along the sweep";
  c.x_label = "reading";
  c.y_label =
      f.kind == protocol::FingerKind::kJamming ? "model - reading (mN/mm)" : "model - reading (µm)";
  Series r{"residual", {}, "#2471a3", false, true};
  if (f.compensator == protocol::CompensatorKind::kPrandtlIshlinskii ||
      f.compensator == protocol::CompensatorKind::kAsymmetricPi) {
    const PlayModel m = ModelOf(f.compensator, f.compensator_params);
    std::vector<double> u;
    for (const SweepSample& s : run.sweep) u.push_back(std::max(0.0, s.drive_pa));
    const std::vector<double> y = m.Simulate(u);
    for (size_t k = 0; k < y.size(); ++k)
      r.points.push_back({static_cast<double>(k), y[k] - run.sweep[k].output});
  }
  c.series = {r};
  return host::RenderSvg(c);
}

std::string LoopsChart(const CalibrationRun& run) {
  Chart c;
  c.title = "Force-depth loops (first press at each condition, up to 12)";
  c.x_label = "depth (µm)";
  c.y_label = "force (mN)";
  // The presses of this session are the last ones of the map (a resumed run lost the others').
  const size_t offset = run.map.size() - std::min(run.map.size(), run.presses.size());
  std::set<std::pair<double, double>> shown;
  for (size_t i = offset; i < run.map.size() && c.series.size() < 12; ++i) {
    if (!shown.insert({run.map[i].bias_kpa, run.map[i].vacuum_kpa}).second) continue;
    const PressCycle& p = run.presses[i - offset];
    Series s{"bias " + Fixed(1000 * run.map[i].bias_kpa, 0) + " Pa, vacuum " +
                 Fixed(1000 * run.map[i].vacuum_kpa, 0) + " Pa",
             {},
             "",
             false,
             false};
    // The rig reads mm and N; the report speaks the calibration file's µm and mN.
    for (const auto& [depth, force] : p.loading) s.points.push_back({1000 * depth, 1000 * force});
    for (const auto& [depth, force] : p.unloading) s.points.push_back({1000 * depth, 1000 * force});
    c.series.push_back(s);
  }
  return host::RenderSvg(c);
}

std::string GridChart(const host::CalibrationFile& f) {
  Chart c;
  c.title = "Stiffness against vacuum, per bias (mean of the repeats)";
  c.x_label = "vacuum (Pa)";
  c.y_label = "stiffness (mN/mm)";
  std::map<double, Series> by_bias;
  for (const host::GridPoint& g : f.grid) {
    Series& s = by_bias[g.bias_pa];
    s.name = "bias " + Fixed(g.bias_pa, 0) + " Pa";
    s.points.push_back({g.vacuum_pa, g.stiffness_mean});
  }
  for (auto& [bias, s] : by_bias) c.series.push_back(s);
  return host::RenderSvg(c);
}

}  // namespace

std::string RenderReport(const CalibrationRun& run) {
  const host::CalibrationFile& f = run.file;
  const bool jamming = f.kind == protocol::FingerKind::kJamming;
  std::string h = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>palpa calibration " +
                  Escape(f.actuator_serial) +
                  "</title><style>body{font-family:sans-serif;max-width:900px;margin:2em "
                  "auto}td,th{padding:2px 8px;text-align:right}"
                  "table{border-collapse:collapse}tr:nth-child(even){background:#f4f4f4}</style></"
                  "head><body>\n";
  h += "<h1>Calibration of " + Escape(f.actuator_serial) + "</h1>\n<p>" +
       (jamming ? "Jamming" : "Pneumatic") + " finger " + std::to_string(f.finger + 1) +
       " of board " + std::to_string(f.board_id) + ", " + Escape(f.date) + ", rig " +
       Escape(f.rig) + ". " + std::to_string(f.quality.points) + " sweep readings; compensator " +
       Escape(host::CompensatorLabel(f)) +
       (run.fit.operators > 0 ? " (" + std::to_string(run.fit.operators_used) + " of its " +
                                    std::to_string(run.fit.operators) + " operators carry a weight)"
                              : std::string()) +
       ", fit residual " + Fixed(f.quality.residual_rms, 1) + " RMS, " +
       Fixed(f.quality.residual_max, 1) + " max (" + (jamming ? "mN/mm" : "µm") + ")" +
       (run.compensator_choice.empty()
            ? std::string()
            : "; model chosen by fitting both: " + Escape(run.compensator_choice)) +
       ".</p>\n";
  if (jamming) {
    h += "<p>Stiffness map: " + Escape(f.quality.protocol) + " protocol, " +
         std::to_string(f.quality.cycles) + " indentation cycles; cross-validated map error " +
         (f.quality.map_error ? Fixed(100 * *f.quality.map_error, 1) + " %" : "unknown") +
         ". Rig time of the run " + Fixed(f.quality.rig_time_s / 60, 1) + " min.</p>\n";
  }
  if (!f.quality.checks.empty()) {
    h += "<table><tr><th>check</th><th>figure</th><th>limit</th><th>unit</th><th>verdict</th><th "
         "style=\"text-align:left\">what was measured</th></tr>\n";
    for (const host::QualityCheck& k : f.quality.checks) {
      h += "<tr><td>" + Escape(k.name) + "</td><td>" + Fixed(k.value, 4) + "</td><td>" +
           Fixed(k.limit, 4) + "</td><td>" + Escape(host::CheckUnit(k.name)) + "</td><td>" +
           (k.passed ? "pass" : "<b>FAIL</b>") + "</td><td style=\"text-align:left\">" +
           Escape(k.detail) + "</td></tr>\n";
    }
    h += "</table>\n";
  }
  if (!f.quality.flags.empty()) {
    h += "<p><b>Flags:</b></p><ul>";
    for (const std::string& flag : f.quality.flags) h += "<li>" + Escape(flag) + "</li>";
    h += "</ul>\n";
  }
  if (f.rising_fit && f.falling_fit) {
    h += "<p>Branch fits, µm against Pa over 10–90 %: rising " + Fixed(f.rising_fit->slope, 4) +
         "·p " + Fixed(f.rising_fit->intercept, 1) + " (R² " + Fixed(f.rising_fit->r2, 3) +
         "), falling " + Fixed(f.falling_fit->slope, 4) + "·p " +
         Fixed(f.falling_fit->intercept, 1) + " (R² " + Fixed(f.falling_fit->r2, 3) +
         "); thesis Table 5-4: 0.0428 and 0.0475 mm/kPa, the same unit.</p>\n";
  }
  if (jamming && f.recommended_bias_pa) {
    h += "<p>Recommended bias: <b>" + Fixed(*f.recommended_bias_pa, 0) +
         " Pa</b> (least press loop area where the stiffness range is "
         "kept).</p>\n<table><tr><th>bias Pa</th><th>vacuum Pa</th>"
         "<th>cycles</th><th>stiffness mN/mm</th><th>spread</th><th>loop mJ</th><th>R² "
         "min</th></tr>\n";
    for (const host::GridPoint& g : f.grid) {
      h += "<tr><td>" + Fixed(g.bias_pa, 0) + "</td><td>" + Fixed(g.vacuum_pa, 0) + "</td><td>" +
           std::to_string(g.cycles) + "</td><td>" + Fixed(g.stiffness_mean, 0) + "</td><td>" +
           Fixed(g.stiffness_spread, 0) + "</td><td>" + Fixed(g.loop_area_mean, 3) + "</td><td>" +
           Fixed(g.r2_min, 4) + "</td></tr>\n";
    }
    h += "</table>\n" + GridChart(f) + LoopsChart(run);
  }
  h += SweepChart(run);
  for (const host::RegulatorCorrection& rc : f.regulator_corrections) h += CorrectionChart(rc);
  h += ResidualChart(run);
  h += "</body></html>\n";
  return h;
}

}  // namespace palpa::calibration
