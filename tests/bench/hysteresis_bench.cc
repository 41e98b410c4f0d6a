// Hysteresis compensation evidence: every method identified on one simulated unit (rig
// measurements, never the truth), scored on a held-out unit with creep and rate dependence on:
// branch gap by the fixed reversal protocol, tracking error on held-out inputs, and the jamming
// history effect swept over 5–20 % of the stiffness range. Prints the tables; with a docs
// directory, writes hysteresis.svg (error against Cortex-M instructions per step) and the table
// block of hysteresis.md.
//   palpa_hysteresis_bench [--quick] [--cost NAME=INSTRUCTIONS ...] [DOCS_DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "doc_block.h"
#include "hysteresis_experiments.h"
#include "palpa/hal/sim/plant_params.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace pt = palpa::testing;
namespace pp = palpa::protocol;
namespace cal = palpa::calibration;
namespace pb = palpa::host;

namespace {

struct Row {
  pt::Method method;
  cal::HysteresisFit fit;
  pt::GapResult gap;
  pt::TrackingResult demo, random, ramps;
};

std::string Figure(double v, int decimals = 1) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

/// "7 / 16": a play model's operators that carry a weight, of those fitted; "-" for others.
std::string Used(const cal::HysteresisFit& fit) {
  if (fit.operators == 0) return "-";
  return std::to_string(fit.operators_used) + " / " + std::to_string(fit.operators);
}

struct JammingRow {
  double history;
  pt::Method method;
  cal::HysteresisFit fit;
  pt::GapResult gap;
  pt::LevelResult levels;      ///< held-out unit
  pt::LevelResult own_levels;  ///< the unit the parameters were identified on, new rig noise
  double injected = 0;
};

/// The held-out figures with the assumed unit spread scaled (the sweep of that assumption): a few
/// methods on the pneumatic finger (gap, absolute error at the reads, demo stimuli) and the
/// jamming finger at h = 10 % (level error on the identified and on the held-out unit).
struct SpreadRow {
  double factor = 1;
  std::map<std::string, pt::GapResult> gap;
  std::map<std::string, pt::TrackingResult> demo;
  std::map<std::string, pt::LevelResult> jam_own, jam_held_out;
};

const char* const kSpreadMethods[] = {"none", "pi(16)", "api(8)"};

SpreadRow SpreadSweep(double factor, int dwell, int seconds, palpa::sim::Effects effects) {
  SpreadRow row;
  row.factor = factor;
  effects.unit_spread = static_cast<float>(factor);
  pt::FingerRig identify_rig({0, 1, 11, effects});
  const pt::Identified id = pt::Identify(identify_rig, cal::SweepPlan{}, dwell);
  palpa::sim::Effects jam_effects;
  jam_effects.history = 0.10f;
  jam_effects.unit_spread = static_cast<float>(factor);
  pt::FingerRig identify_jam({3, 1, 13, jam_effects});
  const pt::Identified jid =
      pt::Identify(identify_jam, cal::SweepPlan{identify_jam.drive_max(), 5000, 4}, 3 * dwell);
  if (!id.error.empty() || !jid.error.empty()) {
    std::fprintf(stderr, "unit spread x%g: identification failed: %s%s\n", factor, id.error.c_str(),
                 jid.error.c_str());
    std::exit(1);
  }
  for (const pt::Method& m : pt::AllMethods()) {
    if (std::find(std::begin(kSpreadMethods), std::end(kSpreadMethods), m.name) ==
        std::end(kSpreadMethods))
      continue;
    const cal::HysteresisFit fit = pt::FitMethod(m, id, identify_rig.drive_max());
    {
      pt::FingerRig rig({0, 2, 22, effects});
      rig.Configure(id.inverse, m.kind, fit.params);
      row.gap[m.name] = pt::BranchGap(rig, id.inverse, dwell);
    }
    {
      pt::FingerRig rig({0, 2, 22, effects});
      rig.Configure(id.inverse, m.kind, fit.params);
      row.demo[m.name] = pt::Track(rig, id.inverse, pt::InputSet::kDemoStimuli, seconds, 1);
    }
    if (m.name == "api(8)") continue;
    const cal::HysteresisFit jfit = pt::FitMethod(m, jid, identify_jam.drive_max());
    {
      pt::FingerRig rig({3, 2, 24, jam_effects});
      rig.Configure(jid.inverse, m.kind, jfit.params);
      row.jam_held_out[m.name] = pt::SettledLevels(rig, jid.inverse, 20, 3 * dwell, 5);
    }
    {
      pt::FingerRig rig({3, 1, 25, jam_effects});
      rig.Configure(jid.inverse, m.kind, jfit.params);
      row.jam_own[m.name] = pt::SettledLevels(rig, jid.inverse, 20, 3 * dwell, 6);
    }
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string docs;
  std::map<std::string, double> cost;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--cost") == 0 && i + 1 < argc) {
      const std::string spec = argv[++i];
      const size_t eq = spec.find('=');
      if (eq == std::string::npos) {
        std::fprintf(stderr, "--cost wants NAME=INSTRUCTIONS, got '%s'\n", spec.c_str());
        return 2;
      }
      cost[spec.substr(0, eq)] = std::atof(spec.c_str() + eq + 1);
    } else if (argv[i][0] == '-') {
      std::fprintf(
          stderr,
          "usage: palpa_hysteresis_bench [--quick] [--cost NAME=INSTRUCTIONS ...] [DOCS_DIR]\n");
      return 2;
    } else {
      docs = argv[i];
    }
  }
  const int dwell = quick ? 800 : 1500;
  const int seconds = quick ? 10 : 40;
  palpa::sim::Effects effects;
  effects.creep = true;
  effects.rate = true;

  // --- pneumatic finger: identification on unit 1, evaluation on unit 2 --------------------
  pt::FingerRig identify_rig({0, 1, 11, effects});
  const pt::Identified id = pt::Identify(identify_rig, cal::SweepPlan{}, dwell);
  if (!id.error.empty()) {
    std::fprintf(stderr, "identification failed: %s\n", id.error.c_str());
    return 1;
  }
  std::printf(
      "== hysteresis: pneumatic finger, identified on unit 1 (%zu sweep points), scored on unit 2 "
      "(creep and rate on) ==\n",
      id.sweep.size());
  std::printf("%-11s %9s %9s %7s | %9s %7s %7s %7s | %8s %8s %8s %8s %8s %8s | %7s\n", "method",
              "fit rms", "fit max", "weights", "gap um", "ratio", "+-5%", "+-20%", "demo rms",
              "max", "rand rms", "max", "ramp rms", "max", "M4 instr");
  std::vector<Row> rows;
  double uncompensated_gap = 0;
  for (const pt::Method& m : pt::AllMethods()) {
    Row row{m, pt::FitMethod(m, id, identify_rig.drive_max()), {}, {}, {}, {}};
    if (m.kind != pp::CompensatorKind::kNone && !row.fit.ok()) {
      std::printf("%-11s fit refused: %s\n", m.name.c_str(), row.fit.error.c_str());
      continue;
    }
    auto evaluate = [&](auto&& body) {
      pt::FingerRig rig({0, 2, 22, effects});
      if (const auto o = rig.Configure(id.inverse, m.kind, row.fit.params); !o.ok()) {
        std::fprintf(stderr, "%s: the board refused the parameters: %s\n", m.name.c_str(),
                     o.message.c_str());
        std::exit(1);
      }
      body(rig);
    };
    evaluate([&](pt::FingerRig& rig) { row.gap = pt::BranchGap(rig, id.inverse, dwell); });
    evaluate([&](pt::FingerRig& rig) {
      row.demo = pt::Track(rig, id.inverse, pt::InputSet::kDemoStimuli, seconds, 1);
    });
    evaluate([&](pt::FingerRig& rig) {
      row.random = pt::Track(rig, id.inverse, pt::InputSet::kBandLimitedRandom, seconds, 2);
    });
    evaluate([&](pt::FingerRig& rig) {
      row.ramps = pt::Track(rig, id.inverse, pt::InputSet::kFastRamps, seconds, 3);
    });
    if (m.kind == pp::CompensatorKind::kNone) uncompensated_gap = row.gap.major_gap;
    const double m4 = cost.count(m.name) ? cost[m.name] : 0;
    std::printf(
        "%-11s %9.1f %9.1f %7s | %9.1f %6.0f%% %7.1f %7.1f | %8.1f %8.1f %8.1f %8.1f %8.1f %8.1f "
        "| %7.0f\n",
        m.name.c_str(), row.fit.residual_rms, row.fit.residual_max, Used(row.fit).c_str(),
        row.gap.major_gap, 100 * row.gap.major_gap / uncompensated_gap, row.gap.nested_gap_small,
        row.gap.nested_gap_large, row.demo.rms, row.demo.max, row.random.rms, row.random.max,
        row.ramps.rms, row.ramps.max, m4);
    rows.push_back(row);
  }

  // --- jamming finger: the vacuum-history effect swept over 5–20 % of the stiffness range ----
  std::printf(
      "\n== hysteresis: jamming finger, vacuum-history effect h of the stiffness range; identified "
      "on unit 1, "
      "scored on unit 2 ==\n");
  std::printf("%5s %-11s %7s %12s %10s | %10s %8s | %10s %8s\n", "h", "method", "weights",
              "gap mN/mm", "residual", "own unit", "max", "held-out", "max");
  std::vector<JammingRow> jamming;
  for (double h : {0.05, 0.10, 0.15, 0.20}) {
    palpa::sim::Effects jam_effects;
    jam_effects.history = static_cast<float>(h);
    pt::FingerRig identify_jam({3, 1, 13, jam_effects});
    const pt::Identified jid =
        pt::Identify(identify_jam, cal::SweepPlan{identify_jam.drive_max(), 5000, 4}, 3 * dwell);
    if (!jid.error.empty()) {
      std::fprintf(stderr, "jamming identification failed: %s\n", jid.error.c_str());
      return 1;
    }
    double injected = 0;
    for (const pt::Method& m : pt::AllMethods()) {
      // One size per family (two for pi) keeps the h sweep readable; sizes are compared above.
      if (m.name != "none" && m.name != "branch(12)" && m.name != "pi(8)" && m.name != "pi(16)" &&
          m.name != "api(8)")
        continue;
      const cal::HysteresisFit fit = pt::FitMethod(m, jid, identify_jam.drive_max());
      if (m.kind != pp::CompensatorKind::kNone && !fit.ok()) {
        std::printf("%5.2f %-11s fit refused: %s\n", h, m.name.c_str(), fit.error.c_str());
        continue;
      }
      JammingRow row{h, m, fit, {}, {}, {}, 0};
      {
        pt::FingerRig rig({3, 2, 23, jam_effects});
        rig.Configure(jid.inverse, m.kind, fit.params);
        row.gap = pt::BranchGap(rig, jid.inverse, 3 * dwell);
      }
      {
        pt::FingerRig rig({3, 2, 24, jam_effects});
        rig.Configure(jid.inverse, m.kind, fit.params);
        row.levels = pt::SettledLevels(rig, jid.inverse, quick ? 8 : 20, 3 * dwell, 5);
      }
      {
        pt::FingerRig rig({3, 1, 25, jam_effects});
        rig.Configure(jid.inverse, m.kind, fit.params);
        row.own_levels = pt::SettledLevels(rig, jid.inverse, quick ? 8 : 20, 3 * dwell, 6);
      }
      if (m.kind == pp::CompensatorKind::kNone) injected = row.gap.major_gap;
      std::printf("%5.2f %-11s %7s %12.1f %9.0f%% | %9.1f%% %7.1f%% | %9.1f%% %7.1f%%\n", h,
                  m.name.c_str(), Used(fit).c_str(), row.gap.major_gap,
                  100 * row.gap.major_gap / injected, 100 * row.own_levels.mean_relative,
                  100 * row.own_levels.max_relative, 100 * row.levels.mean_relative,
                  100 * row.levels.max_relative);
      row.injected = injected;
      jamming.push_back(row);
    }
  }
  // --- the unit spread halved and doubled: how the held-out figures move --------------------
  std::vector<SpreadRow> spread;
  {
    SpreadRow own;  // the runs above are the factor 1
    for (const Row& r : rows) {
      own.gap[r.method.name] = r.gap;
      own.demo[r.method.name] = r.demo;
    }
    for (const JammingRow& r : jamming) {
      if (r.history != 0.10 || r.method.name == "api(8)") continue;  // as the sweep's rows
      own.jam_own[r.method.name] = r.own_levels;
      own.jam_held_out[r.method.name] = r.levels;
    }
    spread.push_back(SpreadSweep(0.5, dwell, seconds, effects));
    spread.push_back(own);
    spread.push_back(SpreadSweep(2, dwell, seconds, effects));
  }
  std::printf("\n== hysteresis: the unit spread (%.1f %%) halved and doubled, held-out unit 2 ==\n",
              100 * palpa::sim::params::kPneumaticUnitSpread);
  for (const SpreadRow& r : spread) {
    for (const char* name : kSpreadMethods) {
      std::printf("  x%-4g %-8s gap %6.1f um, at reads %6.1f um, demo rms %6.1f um", r.factor, name,
                  r.gap.at(name).major_gap, r.gap.at(name).mean_abs_error, r.demo.at(name).rms);
      if (r.jam_held_out.count(name)) {
        std::printf(" | jamming h 10 %%: own %.1f / %.1f %%, held-out %.1f / %.1f %%",
                    100 * r.jam_own.at(name).mean_relative, 100 * r.jam_own.at(name).max_relative,
                    100 * r.jam_held_out.at(name).mean_relative,
                    100 * r.jam_held_out.at(name).max_relative);
      }
      std::printf("\n");
    }
  }
  if (docs.empty()) return 0;

  // --- chart: error against Cortex-M4F instructions per step ---------------------------------
  pb::Chart chart;
  chart.title = "Branch gap on a held-out pneumatic unit against Cortex-M4F cost";
  chart.x_label = "instructions per step (worst, exact count under QEMU)";
  chart.y_label = "major-loop branch gap, 10-90 % (um)";
  // One point per method and size; a family's sizes joined in order (4 → 32 operators, 4 → 16
  // curve points).
  std::map<std::string, pb::Series> families;
  const std::map<std::string, std::string> colors = {
      {"none", "#c0392b"}, {"branch", "#7d3c98"}, {"pi", "#2471a3"}, {"api", "#229954"}};
  for (const Row& r : rows) {
    if (!cost.count(r.method.name)) continue;
    const std::string family = r.method.name.substr(0, r.method.name.find('('));
    pb::Series& series = families[family];
    series.name = family == "none"     ? r.method.name
                  : family == "branch" ? "branch(K), K = 4..16"
                                       : family + "(n), n = 4..32";
    series.color = colors.count(family) ? colors.at(family) : "";
    series.markers = true;  // one point per method and size, a family's sizes joined
    series.joined = family != "none";
    series.points.push_back({cost[r.method.name], r.gap.major_gap});
  }
  for (auto& [family, series] : families) chart.series.push_back(series);
  chart.series.push_back({"goal: gap <= 30 % of none",
                          {{150, 0.3 * uncompensated_gap}, {1000, 0.3 * uncompensated_gap}},
                          "#888",
                          true,
                          false});
  chart.series.push_back(
      {"goal: pi(16) <= 300 instr.", {{300, 0}, {300, uncompensated_gap}}, "#bbb", true, false});
  if (!pb::WriteFileWhole(docs + "/hysteresis.svg", pb::RenderSvg(chart)).ok()) {
    std::fprintf(stderr, "cannot write %s/hysteresis.svg\n", docs.c_str());
    return 1;
  }

  // --- table block of docs/hysteresis.md ------------------------------------------------------
  std::string md;
  md += "Pneumatic finger 0 (thesis-5finger), identified on unit 1 from " +
        std::to_string(id.sweep.size()) +
        " settled rig readings; scored on unit 2 with creep and rate dependence on, truth channel. "
        "Gap: mean |falling - rising| at the static curve's 10-90 % levels; nested: the same at a "
        "level "
        "approached from +-5 % and +-20 % away. Tracking: RMS and max of truth - target, the first "
        "second "
        "after each new held level not scored.\n\n";
  md +=
      "| method | M4F instr/step | fit residual rms | operators with weight | gap (um) | gap / "
      "none "
      "| nested +-5 % | nested +-20 % | abs error at reads (um) | demo rms / max | random rms / "
      "max "
      "| fast ramps rms / max |\n";
  md += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows) {
    const bool branch = r.method.kind == pp::CompensatorKind::kBranch;
    md += "| " + r.method.name + " | " +
          (cost.count(r.method.name) ? Figure(cost[r.method.name], 0) : "-") + " | " +
          (r.method.kind == pp::CompensatorKind::kNone
               ? "-"
               : Figure(r.fit.residual_rms) + (branch ? " Pa" : " um")) +
          " | " + Used(r.fit) + " | " + Figure(r.gap.major_gap) + " | " +
          Figure(100 * r.gap.major_gap / uncompensated_gap, 0) + " % | " +
          Figure(r.gap.nested_gap_small) + " | " + Figure(r.gap.nested_gap_large) + " | " +
          Figure(r.gap.mean_abs_error) + " | " + Figure(r.demo.rms) + " / " + Figure(r.demo.max) +
          " | " + Figure(r.random.rms) + " / " + Figure(r.random.max) + " | " +
          Figure(r.ramps.rms) + " / " + Figure(r.ramps.max) + " |\n";
  }
  md +=
      "\nJamming finger 3, bias 20 kPa: the vacuum-history effect injected at h of the stiffness "
      "range; "
      "identified on unit 1; gap as above in mN/mm (residual = gap / gap without compensation); "
      "level error: |truth - target| / target at random held levels, on the identified unit with "
      "new rig "
      "noise and on held-out unit 2.\n\n";
  md +=
      "| h | method | operators with weight | gap (mN/mm) | residual | level error, own unit "
      "(mean / max) | held-out unit (mean / max) |\n";
  md += "|---:|---|---:|---:|---:|---:|---:|\n";
  for (const JammingRow& r : jamming) {
    md += "| " + Figure(r.history, 2) + " | " + r.method.name + " | " + Used(r.fit) + " | " +
          Figure(r.gap.major_gap) + " | " + Figure(100 * r.gap.major_gap / r.injected, 0) +
          " % | " + Figure(100 * r.own_levels.mean_relative) + " / " +
          Figure(100 * r.own_levels.max_relative) + " % | " + Figure(100 * r.levels.mean_relative) +
          " / " + Figure(100 * r.levels.max_relative) + " % |\n";
  }
  md += "\nThe assumed unit spread (" + Figure(100 * palpa::sim::params::kPneumaticUnitSpread) +
        " % per point, [plant](plant.md)) halved and doubled, everything else as above: held-out "
        "unit 2, identified on unit 1 (both drawn with the scaled spread).\n\n";
  md +=
      "| unit spread | method | pneumatic gap (um) | abs error at reads (um) | demo rms (um) | "
      "jamming h = 10 %: own unit (mean / max) | held-out unit (mean / max) |\n";
  md += "|---:|---|---:|---:|---:|---:|---:|\n";
  for (const SpreadRow& r : spread) {
    for (const char* name : kSpreadMethods) {
      md += "| " + Figure(100 * palpa::sim::params::kPneumaticUnitSpread * r.factor) + " % | " +
            name + " | " + Figure(r.gap.at(name).major_gap) + " | " +
            Figure(r.gap.at(name).mean_abs_error) + " | " + Figure(r.demo.at(name).rms) + " | ";
      if (r.jam_held_out.count(name)) {
        md += Figure(100 * r.jam_own.at(name).mean_relative) + " / " +
              Figure(100 * r.jam_own.at(name).max_relative) + " % | " +
              Figure(100 * r.jam_held_out.at(name).mean_relative) + " / " +
              Figure(100 * r.jam_held_out.at(name).max_relative) + " % |\n";
      } else {
        md += "- | - |\n";
      }
    }
  }
  if (!palpa::bench::ReplaceBlock(docs + "/hysteresis.md", "hysteresis-bench", md)) {
    std::fprintf(stderr, "cannot update the bench block of %s/hysteresis.md\n", docs.c_str());
    return 1;
  }
  std::printf("\nwrote %s/hysteresis.svg and the table block of %s/hysteresis.md\n", docs.c_str(),
              docs.c_str());
  return 0;
}
