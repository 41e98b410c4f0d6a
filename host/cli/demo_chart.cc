// The demo's two-panel chart of true outputs against targets.
#include "demo_chart.h"

#include <cstdio>

namespace palpa::cli {

std::string DemoChartSvg(DemoTraces traces) {
  const bool calibrated = traces.calibrated;
  const double cut_s = traces.CutS();
  auto drawn_at = [&](double t) { return t >= traces.second_pass_s && calibrated ? t - cut_s : t; };
  // Deformation (mm) and stiffness (N/mm) are different quantities: a panel each.
  host::Chart pneumatic_panel, jamming_panel;
  pneumatic_panel.y_label = "deformation (mm), fingers 1-3";
  jamming_panel.y_label = "stiffness (N/mm), fingers 4-5";
  pneumatic_panel.x_label = jamming_panel.x_label = "board time (s)";
  pneumatic_panel.width = jamming_panel.width = 1100;
  pneumatic_panel.height = 380;
  jamming_panel.height = 300;
  if (calibrated) {
    char label[96];
    std::snprintf(label, sizeof(label), "%.0f s of calibration left out", cut_s);
    for (host::Chart* panel : {&pneumatic_panel, &jamming_panel})
      panel->markers.push_back({traces.first_pass_end_s, traces.first_pass_end_s + 2, label});
  }
  const char* names[] = {"finger 1", "finger 2", "finger 3", "finger 4", "finger 5"};
  const char* colours[] = {"#2471a3", "#c0392b", "#229954", "#7d3c98", "#d68910"};
  for (size_t f = 0; f < 5; ++f) {
    host::Chart& panel = f < 3 ? pneumatic_panel : jamming_panel;
    host::Series trace{names[f], {}, colours[f], false, false};
    for (size_t i = 0; i < traces.samples.size(); i += 5) {
      const double t = traces.samples[i].t_s;
      if (calibrated && t > traces.first_pass_end_s && t < traces.second_pass_s) continue;
      trace.points.push_back({drawn_at(t), traces.samples[i].outputs[f]});
    }
    panel.series.push_back(trace);
  }
  for (size_t f = 0; f < 5; ++f) {  // the targets, dashed in the finger's colour
    host::Chart& panel = f < 3 ? pneumatic_panel : jamming_panel;
    host::Series& target = traces.targets[f];
    target.name = std::string("target ") + std::to_string(f + 1);
    target.color = colours[f];
    target.dashed = true;
    panel.series.push_back(target);
    host::Series& second = traces.second[f];
    if (second.points.empty()) continue;
    for (auto& point : second.points) point.first = drawn_at(point.first);
    second.color = colours[f];  // unnamed: the legend lists it once
    second.dashed = true;
    panel.series.push_back(second);
  }
  std::string title =
      "palpa demo: thesis stimuli on a simulated thesis-5finger board (true outputs, targets "
      "dashed)";
  if (calibrated) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "palpa demo: thesis stimuli, nominal, then calibrated from %.0f s (true "
                  "outputs, targets dashed)",
                  drawn_at(traces.second_pass_s));
    title = text;
  }
  return host::RenderSvgPanels({pneumatic_panel, jamming_panel}, title);
}

}  // namespace palpa::cli
