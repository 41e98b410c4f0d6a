// Charts of the plant against the thesis: Table 5-4's major loop, Fig 5-36's stiffness curves and
// press loops. Prints the figures it checks; writes SVGs into a directory.
//   palpa_plant_charts DIR
#include <cmath>
#include <cstdio>
#include <string>

#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/plant.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace ps = palpa::sim;
namespace pb = palpa::host;

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
  chart.title = "Jamming finger: stiffness against vacuum (thesis Fig 5-36(c): 0.7 -> 1.3 N/mm)";
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

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: palpa_plant_charts DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = pb::WriteFileWhole(dir + "/plant_table_5_4.svg", pb::RenderSvg(MajorLoop()));
  ok &= pb::WriteFileWhole(dir + "/plant_fig_5_36.svg", pb::RenderSvg(Stiffness()));
  ok &= pb::WriteFileWhole(dir + "/plant_press_loops.svg", pb::RenderSvg(PressLoops()));
  std::printf("charts: %s/plant_table_5_4.svg plant_fig_5_36.svg plant_press_loops.svg\n",
              dir.c_str());
  return ok ? 0 : 1;
}
