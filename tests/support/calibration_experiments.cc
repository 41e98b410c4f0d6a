// Map scoring against the simulated unit's truth, and the detector runs.
#include "calibration_experiments.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

namespace palpa::testing {
namespace cal = calibration;

namespace {

template <typename Predict>
MapScore Score(SimRig& sim, const cal::MapBox& box, Predict predict) {
  const sim::JammingActuator* unit = sim.board().sim().plant().jamming(kJammingFinger);
  MapScore s;
  double sum = 0;
  int n = 0;
  for (double b = 0; b <= box.bias_max_kpa + 1e-9; b += 2.5) {
    for (double v = 0; v <= box.vacuum_max_kpa + 1e-9; v += 2.5) {
      const double truth =
          unit->StaticStiffness(static_cast<float>(b * 1000), static_cast<float>(-v * 1000));
      const double e = (predict(b, -v) - truth) / truth;
      sum += e * e;
      s.max = std::max(s.max, std::fabs(e));
      ++n;
    }
  }
  s.rms = std::sqrt(sum / n);
  return s;
}

/// Linear interpolation weight of x between the neighbours in a sorted list.
std::pair<size_t, double> Bracket(const std::vector<double>& xs, double x) {
  if (xs.size() < 2) return {0, 0};
  size_t i = 0;
  while (i + 2 < xs.size() && x > xs[i + 1]) ++i;
  const double t = (x - xs[i]) / (xs[i + 1] - xs[i]);
  return {i, std::clamp(t, 0.0, 1.0)};
}

uint8_t VacuumLine(SimRig& sim) { return sim.driven_line(kJammingFinger); }

struct Run {
  cal::RigStatus status;
  cal::CalibrationRun run;
};

Run Calibrate(SimRig& sim, const cal::ProtocolOptions& o, const host::CalibrationFile* previous) {
  cal::Rig rig = sim.rig();
  cal::Journal journal;
  Run r;
  cal::RunInfo info{"JAM-1", 1, "2026-11-22T12:00:00Z", "sim", "JAM-1.csv", previous};
  r.status = cal::RunCalibration(rig, kJammingFinger, o, info, journal, nullptr, &r.run);
  return r;
}

}  // namespace

MapScore ScoreSurface(const std::vector<cal::MapPress>& presses, SimRig& sim,
                      const cal::MapBox& box) {
  const cal::StiffnessSurface surface(cal::StiffnessSamples(presses), box);
  return Score(sim, box, [&](double b, double v) { return surface.Predict(b, v).mean; });
}

MapScore ScoreBilinear(const std::vector<cal::ConditionSummary>& grid, SimRig& sim,
                       const cal::MapBox& box) {
  std::vector<double> biases, vacuums;  // vacuum as a magnitude, ascending
  std::map<std::pair<double, double>, double> at;
  for (const cal::ConditionSummary& g : grid) {
    biases.push_back(g.bias_kpa);
    vacuums.push_back(-g.vacuum_kpa);
    at[{g.bias_kpa, -g.vacuum_kpa}] = g.stiffness_mean;
  }
  for (auto* xs : {&biases, &vacuums}) {
    std::sort(xs->begin(), xs->end());
    xs->erase(std::unique(xs->begin(), xs->end()), xs->end());
  }
  return Score(sim, box, [&](double b, double v) {
    const auto [i, s] = Bracket(biases, b);
    const auto [j, t] = Bracket(vacuums, -v);
    auto k = [&](size_t bi, size_t vi) {
      return at[{biases[std::min(bi, biases.size() - 1)],
                 vacuums[std::min(vi, vacuums.size() - 1)]}];
    };
    return (1 - s) * ((1 - t) * k(i, j) + t * k(i, j + 1)) +
           s * ((1 - t) * k(i + 1, j) + t * k(i + 1, j + 1));
  });
}

cal::ProtocolOptions ShortAdaptiveProtocol() {
  cal::ProtocolOptions o = cal::QuickProtocol();
  o.map_protocol = cal::MapProtocol::kAdaptive;
  o.adaptive.min_cycles = 8;
  o.adaptive.max_cycles = 10;
  return o;
}

std::vector<Detector> AllDetectors() {
  return {Detector::kPoints, Detector::kNoise, Detector::kForceZero, Detector::kLeak,
          Detector::kPrevious};
}

const char* DetectorName(Detector d) {
  switch (d) {
    case Detector::kPoints:
      return "points";
    case Detector::kNoise:
      return "noise";
    case Detector::kForceZero:
      return "force_zero";
    case Detector::kLeak:
      return "leak";
    case Detector::kPrevious:
      return "previous";
  }
  return "?";
}

DetectorCase RunDetectorCase(Detector d, bool inject, uint32_t seed) {
  std::mt19937 rng(seed * 7919u + static_cast<uint32_t>(d));
  auto draw = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const SimRigOptions rig_options{"thesis-5finger", kJammingFinger, 1 + seed % 7, seed, {}};
  cal::ProtocolOptions o = ShortAdaptiveProtocol();
  host::CalibrationFile previous;
  const host::CalibrationFile* previous_ptr = nullptr;
  if (d == Detector::kPrevious) {
    SimRig first(rig_options);
    const Run r = Calibrate(first, o, nullptr);
    if (!r.status.ok()) {
      DetectorCase failed;
      failed.error = "previous run: " + r.status.message;
      return failed;
    }
    previous = r.run.file;
    previous_ptr = &previous;
  }
  SimRigOptions options = rig_options;
  options.seed = seed + 1000;  // another day: new noise, the same actuator and board
  SimRig sim(options);
  if (inject) {
    switch (d) {
      case Detector::kPoints:  // a run cut short: four or five conditions
        o.adaptive.max_cycles = 4 + static_cast<int>(seed % 2);
        o.adaptive.min_cycles = o.adaptive.max_cycles;
        break;
      case Detector::kNoise:  // 3.5–12 × the sensor's class
        sim.force_extra_noise_n = draw(0.006, 0.02);
        break;
      case Detector::kForceZero:  // the zero walks 2–6 mN a minute (a sensor not warmed up)
        sim.force_drift_n_per_s = draw(0.002, 0.006) / 60;
        break;
      case Detector::kLeak:
        sim.Leak(VacuumLine(sim), static_cast<float>(draw(0.05, 0.15)));
        break;
      case Detector::kPrevious:  // worn or swapped: 8–15 % softer or stiffer
        sim.ScaleActuator(static_cast<float>((seed % 2 ? 1 : -1) * draw(0.08, 0.15) + 1));
        break;
    }
  }
  const Run r = Calibrate(sim, o, previous_ptr);
  DetectorCase c;
  c.ran = r.status.ok();
  c.error = r.status.message;
  c.flags = r.run.file.quality.flags;
  for (const host::QualityCheck& k : r.run.file.quality.checks) {
    if (k.name == DetectorName(d)) {
      c.fired = !k.passed;
      c.value = k.value;
      c.limit = k.limit;
      c.detail = k.detail;
    } else if (!k.passed) {
      c.any_other = true;
    }
  }
  return c;
}

}  // namespace palpa::testing
