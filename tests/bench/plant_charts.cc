// Charts of the plant against the thesis: Table 5-4's major loop, Fig 5-36's stiffness curves and
// press loops; the lines' flow: step responses, equivalent time constants and the fastest steps
// with the flow assumptions swept. Prints the figures; writes SVGs into a directory and the flow
// tables into its plant.md.
//   palpa_plant_charts DIR
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "doc_block.h"
#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/fastest_step.h"
#include "palpa/hal/sim/plant.h"
#include "palpa/hal/sim/plant_params.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace ps = palpa::sim;
namespace pb = palpa::host;
namespace pp = palpa::protocol;

namespace {

ps::Plant MakePlant(uint32_t unit = 0) {
  const auto& c = *palpa::core::FindBoardConfig("thesis-5finger");
  ps::PlantOptions o;
  o.level = 2;
  o.unit = unit;
  ps::Plant plant(c.lines.data(), c.line_count, c.fingers.data(), c.finger_count, o);
  plant.SetVented(false);
  return plant;
}

void Hold(ps::Plant& plant, float pa, int ms) {
  plant.SetDacCounts(0, static_cast<uint32_t>(pa / 100000.0f * 4095.0f + 0.5f));
  for (int i = 0; i < ms; ++i) plant.Step();
}

pb::Chart MajorLoop() {
  pb::Chart chart;
  chart.title = "Pneumatic finger: 0 -> 100 -> 0 kPa against thesis Table 5-4";
  chart.x_label = "chamber pressure (kPa)";
  chart.y_label = "deformation (mm)";
  pb::Series up{"simulated, inflation", {}, "#d62728", false, false};
  pb::Series down{"simulated, deflation", {}, "#1f77b4", false, false};
  for (uint32_t unit : {0u}) {
    ps::Plant plant = MakePlant(unit);
    for (int kpa = 0; kpa <= 100; kpa += 2) {
      Hold(plant, static_cast<float>(kpa) * 1000, 1500);
      up.points.push_back(
          {plant.Truth().lines[0].chamber_pa / 1000, plant.Truth().fingers[0].deformation_mm});
    }
    for (int kpa = 100; kpa >= 0; kpa -= 2) {
      Hold(plant, static_cast<float>(kpa) * 1000, 1500);
      down.points.push_back(
          {plant.Truth().lines[0].chamber_pa / 1000, plant.Truth().fingers[0].deformation_mm});
    }
  }
  chart.series.push_back(up);
  chart.series.push_back(down);
  chart.series.push_back({"Table 5-4 inflation fit",
                          {{7.1, 0}, {100, 0.0428 * 100 - 0.3032}},
                          "#d62728",
                          true,
                          false});
  chart.series.push_back({"Table 5-4 deflation fit",
                          {{2.8, 0}, {100, 0.0475 * 100 - 0.1333}},
                          "#1f77b4",
                          true,
                          false});
  // Two other units, to show the spread.
  for (uint32_t unit : {3u, 8u}) {
    ps::Plant plant = MakePlant(unit);
    pb::Series s{"unit " + std::to_string(unit) + ", inflation", {}, "#999", false, false};
    for (int kpa = 0; kpa <= 100; kpa += 5)
      s.points.push_back(
          {static_cast<double>(kpa), plant.pneumatic(0)->RisingMajorMm(static_cast<float>(kpa))});
    chart.series.push_back(s);
  }
  return chart;
}

pb::Chart Stiffness() {
  pb::Chart chart;
  chart.title =
      "Jamming finger: stiffness against vacuum (20 kPa curve anchored at Fig 5-36(c)'s axis "
      "range, 0.7 -> 1.3 N/mm: an assumption)";
  chart.x_label = "vacuum (kPa)";
  chart.y_label = "stiffness (N/mm)";
  ps::Plant plant = MakePlant();
  ps::JammingActuator* j = plant.jamming(3);
  for (float bias : {0.0f, 15000.0f, 20000.0f}) {
    pb::Series s{
        "bias " + std::to_string(static_cast<int>(bias / 1000)) + " kPa", {}, "", bias == 0, false};
    for (int v = 0; v <= 100; v += 2)
      s.points.push_back(
          {-static_cast<double>(v), j->StaticStiffness(bias, -1000.0f * static_cast<float>(v))});
    chart.series.push_back(s);
  }
  // The vacuum-history effect: down from full vacuum sits above the way up (10 % of the range).
  pb::Series down{"20 kPa, from full vacuum back (history 10 %)", {}, "#9467bd", true, false};
  j->Reset();
  j->Step(20000, -100000);
  for (int v = 100; v >= 0; v -= 2)
    down.points.push_back(
        {-static_cast<double>(v), j->Step(20000, -1000.0f * static_cast<float>(v))});
  chart.series.push_back(down);
  return chart;
}

pb::Chart PressLoops() {
  pb::Chart chart;
  chart.title = "Jamming finger: force-depth loops of one 3 mm press";
  chart.x_label = "depth (mm)";
  chart.y_label = "force (N)";
  ps::Plant plant = MakePlant();
  ps::JammingActuator* j = plant.jamming(3);
  std::printf("== plant: jamming press loops (3 mm, loop area / loading work) ==\n");
  for (auto [bias, vacuum] : {std::pair{20000.0f, 0.0f},
                              {20000.0f, -60000.0f},
                              {20000.0f, -100000.0f},
                              {0.0f, -100000.0f}}) {
    j->Reset();
    j->Step(bias, vacuum);
    pb::Series s{"bias " + std::to_string(static_cast<int>(bias / 1000)) + ", vacuum " +
                     std::to_string(static_cast<int>(vacuum / 1000)) + " kPa",
                 {},
                 "",
                 bias == 0,
                 false};
    double load = 0, unload = 0;
    for (int i = 0; i <= 60; ++i)
      s.points.push_back({i * 0.05, j->PressForce(i * 0.05f, 3.0f, true)});
    for (int i = 60; i >= 0; --i)
      s.points.push_back({i * 0.05, j->PressForce(i * 0.05f, 3.0f, false)});
    for (int i = 0; i < 300; ++i) {
      const float d = 3.0f * (static_cast<float>(i) + 0.5f) / 300;
      load += j->PressForce(d, 3.0f, true) * 0.01;
      unload += j->PressForce(d, 3.0f, false) * 0.01;
    }
    std::printf("  %-32s stiffness %.3f N/mm, loading work %.2f mJ, loop %.2f mJ (%.0f %%)\n",
                s.name.c_str(), j->stiffness(), load, load - unload, 100 * (load - unload) / load);
    chart.series.push_back(s);
  }
  return chart;
}

// ---- The lines' flow -------------------------------------------------------------------------

/// Level 1 before the flow model: the chamber followed the outlet through a first-order lag of
/// these time constants (pneumatic, bias, vacuum), behind the regulator's 20 ms.
constexpr double kOldChamberTauS[] = {0.15, 0.1, 0.5};

const char* KindName(pp::LineKind k) {
  return k == pp::LineKind::kVacuum ? "vacuum (jamming)"
         : k == pp::LineKind::kBias ? "bias (air cushion)"
                                    : "pressure (pneumatic)";
}

std::string Fixed(double v, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string Ms(double s) { return s < 0 ? "never" : Fixed(1000 * s, 0) + " ms"; }

/// The chamber's response to the regulator commanded from `from` to `to` (no static errors):
/// the times to 63 % and to within 2 % for good, from the command; outlet and chamber traces.
struct Commanded {
  double t63 = -1, settle = -1;
  std::vector<std::pair<double, double>> outlet, chamber;
};

Commanded Command(pp::LineKind kind, float from, float to, int ms = 15000) {
  ps::RegulatorLine line(ps::NominalRegulatorSetup(kind), 0.001f);
  for (int i = 0; i < 20000; ++i) line.Step(from);
  Commanded c;
  int last_outside = 0;
  for (int i = 1; i <= ms; ++i) {
    line.Step(to);
    const double share = (line.chamber_pa() - from) / (to - from);
    if (c.t63 < 0 && share >= 0.632) c.t63 = i / 1000.0;
    if (std::fabs(line.chamber_pa() - to) > 0.02 * std::fabs(to - from)) last_outside = i;
    c.outlet.push_back({i / 1000.0, line.outlet_pa() / 1000});
    c.chamber.push_back({i / 1000.0, line.chamber_pa() / 1000});
  }
  c.settle = last_outside < ms ? last_outside / 1000.0 : -1;
  return c;
}

/// The old model's 63 % time: dead time, then two first-order lags in a row.
double OldT63(double chamber_tau) {
  const double a = ps::params::kRegulatorLagTauS, b = chamber_tau;
  for (double t = 0;; t += 1e-4) {
    const double y = 1 - (a * std::exp(-t / a) - b * std::exp(-t / b)) / (a - b);
    if (y >= 0.632) return t + ps::params::kRegulatorDeadTimeS;
  }
}

struct StepCase {
  pp::LineKind kind;
  float from, to;
};

const StepCase kFastestSteps[] = {
    {pp::LineKind::kPressure, 0, 10000},      {pp::LineKind::kPressure, 10000, 30000},
    {pp::LineKind::kPressure, 30000, 10000},  {pp::LineKind::kPressure, 30000, 0},
    {pp::LineKind::kPressure, 0, 80000},      {pp::LineKind::kVacuum, 0, -10000},
    {pp::LineKind::kVacuum, -10000, -100000}, {pp::LineKind::kVacuum, -100000, 0},
    {pp::LineKind::kBias, 0, 20000}};

std::string StepName(const StepCase& c) {
  return std::to_string(static_cast<int>(c.from / 1000)) + " → " +
         std::to_string(static_cast<int>(c.to / 1000)) + " kPa";
}

std::string FlowTables() {
  std::string md;
  md +=
      "Equivalent time constants (the chamber's 63 % time from the command, less the 5 ms dead "
      "time), regulator without static errors. Before: the chamber lagged the outlet by a "
      "first-order τ behind the regulator's own 20 ms.\n\n";
  md +=
      "| line | before: chamber τ | before: 63 % | now: small step (±2 kPa mid-range) | now: "
      "full step, 63 % | now: full step, within 2 % |\n|---|---:|---:|---:|---:|---:|\n";
  std::printf("== plant: equivalent time constants ==\n");
  int index = 0;
  for (pp::LineKind kind : {pp::LineKind::kPressure, pp::LineKind::kBias, pp::LineKind::kVacuum}) {
    const float sign = kind == pp::LineKind::kVacuum ? -1.0f : 1.0f;
    const float full = kind == pp::LineKind::kBias ? 20000.0f : 100000.0f;
    const float mid = 0.5f * full;
    const Commanded small = Command(kind, sign * mid, sign * (mid + 2000));
    const Commanded big = Command(kind, 0, sign * full);
    const double dead = ps::params::kRegulatorDeadTimeS;
    const double old_tau = kOldChamberTauS[index++];
    md += std::string("| ") + KindName(kind) + " | " + Ms(old_tau) + " | " +
          Ms(OldT63(old_tau) - dead) + " | " + Ms(small.t63 - dead) + " | " + Ms(big.t63 - dead) +
          " (0 → " + std::to_string(static_cast<int>(sign * full / 1000)) + " kPa) | " +
          Ms(big.settle) + " |\n";
    std::printf(
        "  %-22s before tau %.0f ms (63 %% %.0f ms); now small %.0f ms, full %.0f ms, "
        "2 %% %.0f ms\n",
        KindName(kind), 1000 * old_tau, 1000 * (OldT63(old_tau) - dead), 1000 * (small.t63 - dead),
        1000 * (big.t63 - dead), 1000 * big.settle);
  }
  md +=
      "\nThe plant's fastest steps (`palpa::sim::FastestStep`): after the 5 ms dead time the "
      "main valve fully open towards the target until the chamber gets there, then held. "
      "Reach: the chamber first within 2 % of the step; settle: within it for good; overshoot: "
      "the tube's air evening out after the valve closed. The other columns sweep each assumed "
      "[A] number ×0.5 and ×2 and give the reach.\n\n";
  md +=
      "| step | reach | settle | overshoot | flow ×0.5 / ×2 | band ×0.5 / ×2 | tube ×0.5 / ×2 "
      "| chamber ×0.5 / ×2 |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  std::printf("== plant: fastest steps (reach / settle, ms) ==\n");
  auto reach = [](const StepCase& c, ps::FlowAssumptions a) {
    return ps::FastestStep(ps::NominalRegulatorSetup(c.kind, a), c.from, c.to).reach_s;
  };
  for (const StepCase& c : kFastestSteps) {
    const ps::FastestStepResult r =
        ps::FastestStep(ps::NominalRegulatorSetup(c.kind), c.from, c.to);
    auto pair = [&](ps::FlowAssumptions lo, ps::FlowAssumptions hi) {
      return Fixed(1000 * reach(c, lo), 0) + " / " + Fixed(1000 * reach(c, hi), 0);
    };
    md += "| " + StepName(c) + " (" + (c.kind == pp::LineKind::kBias ? "bias" : "") +
          (c.kind == pp::LineKind::kVacuum ? "vacuum" : "") +
          (c.kind == pp::LineKind::kPressure ? "pneumatic" : "") + ") | " + Ms(r.reach_s) + " | " +
          Ms(r.settle_s) + " | " + Fixed(r.overshoot_pa / 1000, 2) + " kPa | " +
          pair({0.5f, 1, 1, 1}, {2, 1, 1, 1}) + " | " + pair({1, 0.5f, 1, 1}, {1, 2, 1, 1}) +
          " | " + pair({1, 1, 0.5f, 1}, {1, 1, 2, 1}) + " | " +
          pair({1, 1, 1, 0.5f}, {1, 1, 1, 2}) + " |\n";
    std::printf("  %-22s %s reach %6.1f settle %6.1f overshoot %.2f kPa\n", StepName(c).c_str(),
                KindName(c.kind), 1000 * r.reach_s, 1000 * r.settle_s, r.overshoot_pa / 1000);
  }
  return md;
}

class TraceSeries final : public ps::FastestStepTrace {
 public:
  explicit TraceSeries(pb::Series* s) : s_(s) {}
  void Point(float t, float chamber_pa) override { s_->points.push_back({t, chamber_pa / 1000}); }

 private:
  pb::Series* s_;
};

/// Step responses of a line: the regulator commanded (outlet, where the sensor sits, and the
/// chamber) against the fastest step's chamber.
pb::Chart LineSteps(const char* title, const std::vector<StepCase>& steps, double seconds) {
  pb::Chart chart;
  chart.title = title;
  chart.x_label = "time from the command (s)";
  chart.y_label = "pressure (kPa)";
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c"};
  int i = 0;
  for (const StepCase& c : steps) {
    const std::string name = StepName(c);
    const Commanded k = Command(c.kind, c.from, c.to, static_cast<int>(seconds * 1000));
    pb::Series outlet{name + ": outlet (sensor)", k.outlet, colours[i], true, false};
    pb::Series chamber{name + ": chamber", k.chamber, colours[i], false, false};
    pb::Series fastest{name + ": fastest step's chamber", {}, "#999", true, false};
    TraceSeries trace(&fastest);
    ps::FastestStep(ps::NominalRegulatorSetup(c.kind), c.from, c.to, static_cast<float>(seconds),
                    &trace);
    chart.series.push_back(outlet);
    chart.series.push_back(chamber);
    chart.series.push_back(fastest);
    ++i;
  }
  return chart;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: palpa_plant_charts DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = pb::WriteFileWhole(dir + "/plant_table_5_4.svg", pb::RenderSvg(MajorLoop())).ok();
  ok &= pb::WriteFileWhole(dir + "/plant_fig_5_36.svg", pb::RenderSvg(Stiffness())).ok();
  ok &= pb::WriteFileWhole(dir + "/plant_press_loops.svg", pb::RenderSvg(PressLoops())).ok();
  ok &= pb::WriteFileWhole(
            dir + "/plant_pressure_steps.svg",
            pb::RenderSvg(LineSteps("Pneumatic line: regulator commanded, against the fastest step",
                                    {{pp::LineKind::kPressure, 0, 10000},
                                     {pp::LineKind::kPressure, 30000, 0},
                                     {pp::LineKind::kPressure, 0, 80000}},
                                    0.3)))
            .ok();
  ok &= pb::WriteFileWhole(
            dir + "/plant_vacuum_steps.svg",
            pb::RenderSvg(LineSteps("Vacuum line: regulator commanded, against the fastest step",
                                    {{pp::LineKind::kVacuum, 0, -10000},
                                     {pp::LineKind::kVacuum, -10000, -100000},
                                     {pp::LineKind::kVacuum, -100000, 0}},
                                    4.0)))
            .ok();
  ok &= palpa::bench::ReplaceBlock(dir + "/plant.md", "plant-flow", FlowTables());
  std::printf(
      "charts: %s/plant_table_5_4.svg plant_fig_5_36.svg plant_press_loops.svg "
      "plant_pressure_steps.svg plant_vacuum_steps.svg; tables in plant.md\n",
      dir.c_str());
  return ok ? 0 : 1;
}
