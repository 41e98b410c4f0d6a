// Calibration: speed against accuracy of the stiffness map (thesis grid at 1, 2 and 8 repeats,
// the adaptive protocol cycle by cycle) across seeds and held-out units, and every failure
// detector's detection and false-positive rates. Prints the figures; with a docs directory,
// writes docs/calibration.svg, docs/calibration_time.svg and the block in docs/calibration.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "calibration_experiments.h"
#include "doc_block.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace {

namespace cal = palpa::calibration;
namespace pt = palpa::testing;
namespace ph = palpa::host;

std::string Figure(double v, int decimals = 1) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

/// One protocol run on one seed: its error after so many cycles and minutes of map time.
struct Point {
  int cycles = 0;
  double minutes = 0;
  pt::MapScore surface, bilinear;
  double estimate = 0;  ///< what the rig thought its map error was
};

struct Seeded {
  std::vector<Point> thesis;    ///< repeats 1, 2, 8
  std::vector<Point> adaptive;  ///< after every cycle
  int stop = -1;                ///< index in adaptive where the default rule stopped
};

pt::SimRig MakeRig(uint32_t seed, palpa::sim::Effects effects) {
  // Held-out units: never the nominal one, a different unit for every seed.
  return pt::SimRig({"thesis-5finger", pt::kJammingFinger, 20 + seed, seed, effects});
}

Point ThesisRun(uint32_t seed, int repeats, palpa::sim::Effects effects = {}) {
  pt::SimRig sim = MakeRig(seed, effects);
  cal::Rig rig = sim.rig();
  double zero = 0;
  cal::RigStatus s = cal::ZeroOnVentedSurface(rig, pt::kJammingFinger, {}, &zero);
  nlohmann::json state;
  std::vector<cal::MapPress> presses;
  const double start = rig.time.Now();
  if (s.ok()) {
    s = cal::RunGridMap(rig, pt::kJammingFinger, zero, cal::PressSettings{}, {0, 10, 20},
                        {0, -50, -100}, repeats, state, {}, &presses);
  }
  if (!s.ok()) {
    std::fprintf(stderr, "thesis run, seed %u: %s\n", seed, s.message.c_str());
    std::exit(1);
  }
  Point p;
  p.cycles = static_cast<int>(presses.size());
  p.minutes = (rig.time.Now() - start) / 60;
  p.surface = pt::ScoreSurface(presses, sim);
  p.bilinear = pt::ScoreBilinear(cal::SummariseConditions(presses), sim);
  p.estimate = cal::EstimateMap(presses, {}).map_error;
  return p;
}

Seeded AdaptiveRun(uint32_t seed, int budget, palpa::sim::Effects effects = {}) {
  Seeded out;
  pt::SimRig sim = MakeRig(seed, effects);
  cal::Rig rig = sim.rig();
  double zero = 0;
  cal::RigStatus s = cal::ZeroOnVentedSurface(rig, pt::kJammingFinger, {}, &zero);
  const cal::AdaptiveOptions defaults;
  cal::AdaptiveOptions o;  // never stops early: the whole trajectory, choices as the default's
  o.target_error = 0;
  o.max_cycles = budget;
  const double start = rig.time.Now();
  cal::MapHooks hooks;
  hooks.after_press = [&](const std::vector<cal::MapPress>& presses) {
    Point p;
    p.cycles = static_cast<int>(presses.size());
    p.minutes = (rig.time.Now() - start) / 60;
    p.surface = pt::ScoreSurface(presses, sim);
    const cal::MapEstimate e = cal::EstimateMap(presses, {});
    p.estimate = e.map_error;
    out.adaptive.push_back(p);
    if (out.stop < 0 && p.cycles >= defaults.min_cycles && e.repeated_conditions > 0 &&
        e.map_error <= defaults.target_error) {
      out.stop = static_cast<int>(out.adaptive.size()) - 1;
    }
  };
  nlohmann::json state;
  std::vector<cal::MapPress> presses;
  cal::MapEstimate estimate;
  if (s.ok()) {
    s = cal::RunAdaptiveMap(rig, pt::kJammingFinger, zero, cal::PressSettings{}, o, state, hooks,
                            &presses, &estimate);
  }
  if (!s.ok()) {
    std::fprintf(stderr, "adaptive run, seed %u: %s\n", seed, s.message.c_str());
    std::exit(1);
  }
  if (out.stop < 0 || out.adaptive[out.stop].cycles > defaults.max_cycles) {
    out.stop = std::min<int>(defaults.max_cycles, static_cast<int>(out.adaptive.size())) - 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 6, detector_seeds = 10, budget = 24, sweep_seeds = 3;
  std::string docs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      seeds = 2;
      detector_seeds = 2;
      sweep_seeds = 1;
      budget = 18;
    } else if (argv[i][0] != '-') {
      docs = argv[i];
    } else {
      std::fprintf(stderr, "usage: palpa_calibration_bench [--quick] [DOCS_DIR]\n");
      return 2;
    }
  }

  // 1. Speed against accuracy.
  std::vector<Seeded> runs;
  for (int s = 1; s <= seeds; ++s) {
    Seeded r = AdaptiveRun(static_cast<uint32_t>(s), budget);
    for (int repeats : {1, 2, 8}) r.thesis.push_back(ThesisRun(static_cast<uint32_t>(s), repeats));
    runs.push_back(r);
  }
  auto mean = [&](auto pick) {
    double sum = 0;
    for (const Seeded& r : runs) sum += pick(r);
    return sum / static_cast<double>(runs.size());
  };
  auto worst = [&](auto pick) {
    double w = 0;
    for (const Seeded& r : runs) w = std::max(w, pick(r));
    return w;
  };
  std::printf("== stiffness map: held-out error against cycles (%d seeds, held-out units) ==\n",
              seeds);
  std::string table =
      "| protocol | cycles | map rig time (min) | held-out error RMS (mean / worst seed) | max "
      "(mean / worst seed) | the rig's own estimate |\n|---|---|---|---|---|---|\n";
  auto row = [&](const std::string& name, double cycles, double minutes, double rms, double rms_w,
                 double max, double max_w, double estimate) {
    std::printf(
        "  %-34s cycles %5.1f  %6.1f min  rms %5.2f %% (worst %5.2f)  max %5.2f %% (worst %5.2f)  "
        "est %5.2f %%\n",
        name.c_str(), cycles, minutes, 100 * rms, 100 * rms_w, 100 * max, 100 * max_w,
        100 * estimate);
    table += "| " + name + " | " + Figure(cycles, 1) + " | " + Figure(minutes, 1) + " | " +
             Figure(100 * rms, 2) + " / " + Figure(100 * rms_w, 2) + " % | " +
             Figure(100 * max, 1) + " / " + Figure(100 * max_w, 1) + " % | " +
             Figure(100 * estimate, 2) + " % |\n";
  };
  const char* repeat_names[] = {"1", "2", "8"};
  for (size_t k = 0; k < 3; ++k) {
    for (bool bilinear : {true, false}) {
      auto pick = [&](const Seeded& r) {
        return bilinear ? r.thesis[k].bilinear : r.thesis[k].surface;
      };
      row(std::string("thesis 3×3 × ") + repeat_names[k] + (bilinear ? ", bilinear" : ", surface"),
          mean([&](const Seeded& r) { return r.thesis[k].cycles; }),
          mean([&](const Seeded& r) { return r.thesis[k].minutes; }),
          mean([&](const Seeded& r) { return pick(r).rms; }),
          worst([&](const Seeded& r) { return pick(r).rms; }),
          mean([&](const Seeded& r) { return pick(r).max; }),
          worst([&](const Seeded& r) { return pick(r).max; }),
          mean([&](const Seeded& r) { return r.thesis[k].estimate; }));
    }
  }
  auto at_stop = [](const Seeded& r) { return r.adaptive[static_cast<size_t>(r.stop)]; };
  row("adaptive (stops on its own estimate)",
      mean([&](const Seeded& r) { return at_stop(r).cycles; }),
      mean([&](const Seeded& r) { return at_stop(r).minutes; }),
      mean([&](const Seeded& r) { return at_stop(r).surface.rms; }),
      worst([&](const Seeded& r) { return at_stop(r).surface.rms; }),
      mean([&](const Seeded& r) { return at_stop(r).surface.max; }),
      worst([&](const Seeded& r) { return at_stop(r).surface.max; }),
      mean([&](const Seeded& r) { return at_stop(r).estimate; }));
  int most_cycles = 0;
  for (const Seeded& r : runs) most_cycles = std::max(most_cycles, at_stop(r).cycles);
  std::printf("  adaptive: stopped after %d cycles at most (goal: ≤ 18 cycles, ≤ 3 %% held-out)\n",
              most_cycles);

  // 1b. The assumptions swept: the jamming bias's [A] numbers and the unit spread, each ×0.5 and
  // ×2 — how much of the adaptive protocol's lead over the grid holds.
  std::printf("== stiffness map: assumptions swept (%d seeds each) ==\n", sweep_seeds);
  std::string sweep_table =
      "| assumption | thesis 3×3, bilinear: RMS / max | thesis 3×3, surface: RMS / max | "
      "adaptive: cycles, RMS / max |\n|---|---|---|---|\n";
  struct Sweep {
    const char* name;
    palpa::sim::Effects effects;
  };
  std::vector<Sweep> sweeps;
  for (float f : {0.5f, 2.0f}) {
    Sweep b{f < 1 ? "jamming bias effect ×0.5" : "jamming bias effect ×2", {}};
    b.effects.bias_stiffening = b.effects.bias_widening = f;
    sweeps.push_back(b);
  }
  for (float f : {0.5f, 2.0f}) {
    Sweep u{f < 1 ? "unit spread ×0.5" : "unit spread ×2", {}};
    u.effects.unit_spread = f;
    sweeps.push_back(u);
  }
  for (const Sweep& w : sweeps) {
    double grid_b = 0, grid_b_max = 0, grid_s = 0, grid_s_max = 0, ad = 0, ad_max = 0, cycles = 0;
    for (int s = 1; s <= sweep_seeds; ++s) {
      const Point g = ThesisRun(static_cast<uint32_t>(s), 1, w.effects);
      const Seeded a = AdaptiveRun(static_cast<uint32_t>(s), budget, w.effects);
      const Point& stop = a.adaptive[static_cast<size_t>(a.stop)];
      grid_b += g.bilinear.rms / sweep_seeds;
      grid_b_max += g.bilinear.max / sweep_seeds;
      grid_s += g.surface.rms / sweep_seeds;
      grid_s_max += g.surface.max / sweep_seeds;
      ad += stop.surface.rms / sweep_seeds;
      ad_max += stop.surface.max / sweep_seeds;
      cycles += static_cast<double>(stop.cycles) / sweep_seeds;
    }
    std::printf(
        "  %-28s grid bilinear %5.2f / %5.1f %%  surface %5.2f / %5.1f %%  adaptive %4.1f "
        "cycles %5.2f / %5.1f %%\n",
        w.name, 100 * grid_b, 100 * grid_b_max, 100 * grid_s, 100 * grid_s_max, cycles, 100 * ad,
        100 * ad_max);
    sweep_table += std::string("| ") + w.name + " | " + Figure(100 * grid_b, 2) + " / " +
                   Figure(100 * grid_b_max, 1) + " % | " + Figure(100 * grid_s, 2) + " / " +
                   Figure(100 * grid_s_max, 1) + " % | " + Figure(cycles, 1) + ", " +
                   Figure(100 * ad, 2) + " / " + Figure(100 * ad_max, 1) + " % |\n";
  }

  // 2. The detectors.
  std::printf("== failure detectors (%d seeds each, injected and clean) ==\n", detector_seeds);
  std::string detectors =
      "| detector | detected (injected) | false positives (clean) | injected fault "
      "|\n|---|---|---|---|\n";
  const char* faults[] = {
      "run cut to 4–5 cycles", "3.5–12 × the sensor's noise", "zero drifting 2–6 mN per minute",
      "vacuum line leak, 5–15 % of the tubing's conductance", "actuator 8–15 % softer or stiffer"};
  for (pt::Detector d : pt::AllDetectors()) {
    int detected = 0, false_positive = 0, failed = 0;
    for (int s = 1; s <= detector_seeds; ++s) {
      const pt::DetectorCase bad = pt::RunDetectorCase(d, true, static_cast<uint32_t>(s));
      const pt::DetectorCase clean = pt::RunDetectorCase(d, false, static_cast<uint32_t>(s));
      if (!bad.ran || !clean.ran) {
        ++failed;
        std::fprintf(stderr, "  %s seed %d did not finish: %s%s\n", pt::DetectorName(d), s,
                     bad.error.c_str(), clean.error.c_str());
      }
      if (clean.fired || clean.any_other || !bad.fired) {
        for (const std::string& f : (bad.fired ? clean : bad).flags) {
          std::fprintf(stderr, "    %s seed %d %s: %s\n", pt::DetectorName(d), s,
                       bad.fired ? "clean" : "injected, missed", f.c_str());
        }
        if (!bad.fired) std::fprintf(stderr, "    missed: %s\n", bad.detail.c_str());
      }
      detected += bad.fired;
      false_positive += clean.fired || clean.any_other;
    }
    std::printf("  %-11s detected %2d/%d  false positives %2d/%d  unfinished %d\n",
                pt::DetectorName(d), detected, detector_seeds, false_positive, detector_seeds,
                failed);
    detectors += std::string("| ") + pt::DetectorName(d) + " | " + std::to_string(detected) + "/" +
                 std::to_string(detector_seeds) + " | " + std::to_string(false_positive) + "/" +
                 std::to_string(detector_seeds) + " | " + faults[static_cast<int>(d)] + " |\n";
  }
  if (docs.empty()) return 0;

  // Charts: error against cycles and against map rig time, mean over seeds.
  for (bool time : {false, true}) {
    ph::Chart c;
    c.title = std::string("Stiffness map: held-out RMS error against ") +
              (time ? "rig time" : "indentation cycles") + " (mean of " + std::to_string(seeds) +
              " seeds)";
    c.x_label = time ? "map rig time (min)" : "indentation cycles";
    c.y_label = "held-out RMS error (% of value)";
    c.log_x = true;
    ph::Series adaptive{"adaptive, after each cycle", {}, "#c0392b", false, false};
    for (size_t i = 4; i < runs.front().adaptive.size(); ++i) {  // from the five-point start
      double e = 0, x = 0;
      for (const Seeded& r : runs) {
        e += r.adaptive[i].surface.rms / runs.size();
        x += (time ? r.adaptive[i].minutes : r.adaptive[i].cycles) /
             static_cast<double>(runs.size());
      }
      adaptive.points.push_back({x, 100 * e});
    }
    ph::Series stops{"adaptive, where it stopped", {}, "#c0392b", false, true};
    ph::Series grid{"thesis 3×3, 1/2/8 repeats", {}, "#2c3e50", false, true};
    ph::Series grid_bilinear{"thesis, bilinear", {}, "#7f8c8d", true, false};
    for (const Seeded& r : runs) {
      stops.points.push_back(
          {time ? at_stop(r).minutes : at_stop(r).cycles, 100 * at_stop(r).surface.rms});
    }
    for (size_t k = 0; k < 3; ++k) {
      const double x =
          mean([&](const Seeded& r) { return time ? r.thesis[k].minutes : r.thesis[k].cycles; });
      grid.points.push_back(
          {x, 100 * mean([&](const Seeded& r) { return r.thesis[k].surface.rms; })});
      grid_bilinear.points.push_back(
          {x, 100 * mean([&](const Seeded& r) { return r.thesis[k].bilinear.rms; })});
    }
    ph::Series goal{
        "goal: 3 %", {{time ? 1.0 : 5.0, 3}, {time ? 100.0 : 72.0, 3}}, "#27ae60", true, false};
    c.series = {adaptive, stops, grid, grid_bilinear, goal};
    ph::WriteFileWhole(docs + (time ? "/calibration_time.svg" : "/calibration.svg"),
                       ph::RenderSvg(c));
  }
  const std::string block =
      "Speed against accuracy (" + std::to_string(seeds) + " seeds, each a held-out unit):\n\n" +
      table + "\nThe assumptions swept (" + std::to_string(sweep_seeds) +
      " seeds each; the thesis grid at one repeat, the adaptive protocol where its rule "
      "stopped):\n\n" +
      sweep_table + "\nFailure detectors (" + std::to_string(detector_seeds) + " seeds each):\n\n" +
      detectors;
  if (!palpa::bench::ReplaceBlock(docs + "/calibration.md", "calibration-bench", block)) {
    std::fprintf(stderr, "%s/calibration.md has no calibration-bench block\n", docs.c_str());
    return 1;
  }
  return 0;
}
