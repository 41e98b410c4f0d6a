// One pass of the demo's stimuli, and the summary of the passes.
#include "demo_pass.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "cli.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;

}  // namespace

bool PlaySteps(host::Device& d, host::TruthReader& truth, const host::LevelTables& levels,
               const std::vector<Step>& steps, std::vector<host::Series>& targets,
               PassFigures& figures) {
  const pp::HelloReply board = d.info();
  std::fprintf(
      TextOut(),
      "  step  fingers      target                         achieved (true)                settled  "
      " latency\n");
  std::vector<int> previous(board.finger_count, 0);
  for (size_t n = 0; n < steps.size(); ++n) {
    const Step& s = steps[n];
    std::vector<host::FingerRequest> requests;
    std::vector<double> want(board.finger_count, 0);
    for (size_t i = 0; i < s.levels.size(); ++i) {
      const uint8_t finger = static_cast<uint8_t>(s.jamming ? 3 + i : i);
      const host::Request level{host::TargetKind::kLevel, static_cast<double>(s.levels[i])};
      requests.push_back({finger, level});
      const host::Mapped m =
          host::MapRequest(board.fingers[finger], levels, d.curves(finger), level);
      // Level 0 of a jamming finger is "off" (released vacuum): the nominal map's stiffness there,
      // 0.7 N/mm, the bottom of Fig 5-36(c)'s axis (an axis-range assumption).
      want[finger] = s.jamming ? (m.target == 0 ? 0.7 : m.target / 1000.0) : m.target / 1000.0;
    }
    const double t0 = truth.now_s();
    const auto sent = std::chrono::steady_clock::now();
    const host::Outcome o = d.Set(requests);
    const double latency_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
    if (!o.ok()) {
      Fail("demo", o.status, "step " + std::to_string(n + 1) + ": " + o.message);
      return false;
    }
    const double hold_s = s.jamming ? 3.5 : 1.6;  // board time: vacuum chambers are slow
    while (truth.now_s() < t0 + hold_s) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const auto trace = truth.Since(t0);
    const std::vector<double>& achieved = trace.back().outputs;
    // Settled: from when every driven finger stays within 5 % (0.03 mm near zero) of where it ends.
    double settled_s = 0;
    for (const auto& sample : trace) {
      for (const auto& r : requests) {
        const double band = std::max(0.05 * std::fabs(achieved[r.finger]), s.jamming ? 0.01 : 0.03);
        if (std::fabs(sample.outputs[r.finger] - achieved[r.finger]) > band)
          settled_s = sample.t_s - t0;
      }
    }
    std::string target_text, achieved_text;
    char cell[32];
    const int k = s.jamming ? 1 : 0;
    for (size_t i = 0; i < requests.size(); ++i) {
      const uint8_t f = requests[i].finger;
      std::snprintf(cell, sizeof(cell), "%5.2f ", want[f]);
      target_text += cell;
      std::snprintf(cell, sizeof(cell), "%5.2f ", achieved[f]);
      achieved_text += cell;
      if (want[f] > 0.1) {
        const double pct = 100 * std::fabs(achieved[f] - want[f]) / want[f];
        figures.worst_pct[k] = std::max(figures.worst_pct[k], pct);
        figures.sum_sq_pct[k] += pct * pct;
        ++figures.count[k];
      }
      if (!s.jamming && s.levels[i] == 1 && previous[f] != 1) {
        (previous[f] == 0 ? figures.l1_from_below : figures.l1_from_above) += achieved[f];
        ++(previous[f] == 0 ? figures.n_below : figures.n_above);
      }
      previous[f] = s.levels[i];
      targets[f].points.push_back({t0, want[f]});
      targets[f].points.push_back({t0 + hold_s, want[f]});
    }
    std::fprintf(TextOut(), "  %2zu/%zu  %-12s %-4s %-25s %-4s %-25s %5.2f s  %5.1f ms\n", n + 1,
                 steps.size(), s.names.c_str(), s.jamming ? "N/mm" : "mm", target_text.c_str(),
                 s.jamming ? "N/mm" : "mm", achieved_text.c_str(), settled_s, latency_ms);
    std::fflush(stdout);
  }
  return true;
}

void PrintSummary(const PassFigures& nominal, const PassFigures* calibrated,
                  const std::string& compensator) {
  auto mean = [](double sum, int n) { return n > 0 ? sum / n : 0.0; };
  std::fprintf(TextOut(), "\n%-44s %-22s %s\n", "", "  nominal, none",
               calibrated ? compensator.c_str() : "");
  auto row = [&](const char* what, double a, double b, const char* unit) {
    std::fprintf(TextOut(), "%-44s %6.1f %-15s", what, a, unit);
    if (calibrated) std::fprintf(TextOut(), " %6.1f %s", b, unit);
    std::fprintf(TextOut(), "\n");
  };
  row("pneumatic fingers: largest |error| / target", nominal.worst_pct[0],
      calibrated ? calibrated->worst_pct[0] : 0, "%");
  row("pneumatic fingers: RMS |error| / target", nominal.Rms(0),
      calibrated ? calibrated->Rms(0) : 0, "%");
  auto gap = [&](const PassFigures& p) {
    return 1000 * (mean(p.l1_from_above, p.n_above) - mean(p.l1_from_below, p.n_below));
  };
  row("level 1 from above minus from below", gap(nominal), calibrated ? gap(*calibrated) : 0, "um");
  std::fprintf(TextOut(), "%-44s %6.1f %%\n", "jamming fingers: largest |error| / target",
               nominal.worst_pct[1]);
}

}  // namespace palpa::cli
