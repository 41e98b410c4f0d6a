// Identification, the branch-gap protocol and held-out input sets on the simulated rig.
#include "hysteresis_experiments.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace palpa::testing {
namespace pp = protocol;
namespace cal = calibration;

std::vector<Method> AllMethods() {
  using K = pp::CompensatorKind;
  return {{"none", K::kNone, 0},
          {"branch(4)", K::kBranch, 4},
          {"branch(8)", K::kBranch, 8},
          {"branch(12)", K::kBranch, 12},
          {"branch(16)", K::kBranch, 16},
          {"pi(4)", K::kPrandtlIshlinskii, 4},
          {"pi(8)", K::kPrandtlIshlinskii, 8},
          {"pi(16)", K::kPrandtlIshlinskii, 16},
          {"pi(32)", K::kPrandtlIshlinskii, 32},
          {"api(4)", K::kAsymmetricPi, 4},
          {"api(8)", K::kAsymmetricPi, 8},
          {"api(16)", K::kAsymmetricPi, 16},
          {"api(32)", K::kAsymmetricPi, 32}};
}

Identified Identify(FingerRig& rig, const cal::SweepPlan& plan, int dwell_ms) {
  Identified id;
  id.sweep = rig.Sweep(cal::SweepDrives(plan), dwell_ms);
  auto inverse = cal::FitStaticInverse(id.sweep, 16, rig.jamming());
  id.inverse = std::move(inverse.value);
  id.error = std::move(inverse.message);
  return id;
}

cal::HysteresisFit FitMethod(const Method& m, const Identified& id, double drive_max) {
  return cal::FitCompensator(m.kind, m.size, id.sweep, drive_max);
}

double OutputAtShare(const std::vector<pp::InversePoint>& inverse, double share, double drive_max) {
  const double drive = share * drive_max;
  auto drive_of = [](const pp::InversePoint& p) {
    return std::fabs(static_cast<double>(p.setpoint_pa));
  };
  if (drive <= drive_of(inverse.front())) return inverse.front().output;
  for (size_t k = 1; k < inverse.size(); ++k) {
    if (drive_of(inverse[k]) >= drive) {
      const double t =
          (drive - drive_of(inverse[k - 1])) / (drive_of(inverse[k]) - drive_of(inverse[k - 1]));
      return inverse[k - 1].output + t * (inverse[k].output - inverse[k - 1].output);
    }
  }
  return inverse.back().output;
}

GapResult BranchGap(FingerRig& rig, const std::vector<pp::InversePoint>& inverse, int dwell_ms) {
  GapResult r;
  const double max = rig.drive_max();
  std::vector<double> rising, falling, levels;
  for (int k = 1; k <= 9; ++k) levels.push_back(OutputAtShare(inverse, 0.1 * k, max));
  double error_sum = 0;
  int reads = 0;
  auto read = [&](double target) {
    rig.Follow(target, dwell_ms);
    const double truth = rig.TruthOutput();
    error_sum += std::fabs(truth - target);
    ++reads;
    return truth;
  };
  rig.Follow(0, dwell_ms);  // vented: the major loop starts from a wiped memory
  for (double level : levels) rising.push_back(read(level));
  read(OutputAtShare(inverse, 1.0, max) - 1);  // the top reversal
  for (auto it = levels.rbegin(); it != levels.rend(); ++it)
    falling.insert(falling.begin(), read(*it));
  rig.Follow(0, dwell_ms);
  for (size_t k = 0; k < levels.size(); ++k) {
    const double gap = std::fabs(falling[k] - rising[k]);
    r.major_gap += gap / static_cast<double>(levels.size());
    r.major_gap_max = std::max(r.major_gap_max, gap);
  }
  // Nested reversals: reach a level from below, go up by the amplitude, come back to it.
  for (double amplitude : {0.05, 0.20}) {
    double sum = 0;
    for (double share : {0.3, 0.5, 0.7}) {
      const double level = OutputAtShare(inverse, share, max);
      rig.Follow(OutputAtShare(inverse, share - amplitude, max), dwell_ms);
      const double from_below = read(level);
      rig.Follow(OutputAtShare(inverse, share + amplitude, max), dwell_ms);
      const double from_above = read(level);
      sum += std::fabs(from_above - from_below) / 3.0;
    }
    (amplitude < 0.1 ? r.nested_gap_small : r.nested_gap_large) = sum;
  }
  r.mean_abs_error = error_sum / reads;
  return r;
}

LevelResult SettledLevels(FingerRig& rig, const std::vector<pp::InversePoint>& inverse, int levels,
                          int dwell_ms, uint32_t seed) {
  LevelResult r;
  const double max = rig.drive_max();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> share(0.1, 0.9);
  rig.Follow(0, 400);
  for (int k = 0; k < levels; ++k) {
    const double target = OutputAtShare(inverse, share(rng), max);
    rig.Follow(target, dwell_ms);
    const double e = std::fabs(rig.TruthOutput() - target) / target;
    r.mean_relative += e / levels;
    r.max_relative = std::max(r.max_relative, e);
  }
  return r;
}

const char* InputSetName(InputSet s) {
  switch (s) {
    case InputSet::kDemoStimuli:
      return "demo stimuli";
    case InputSet::kBandLimitedRandom:
      return "band-limited random";
    case InputSet::kFastRamps:
      return "fast ramps";
  }
  return "?";
}

TrackingResult Track(FingerRig& rig, const std::vector<pp::InversePoint>& inverse, InputSet set,
                     int seconds, uint32_t seed) {
  TrackingResult r;
  const double max = rig.drive_max();
  const double lo = OutputAtShare(inverse, 0.1, max), hi = OutputAtShare(inverse, 0.9, max);
  std::mt19937 rng(seed);
  double sum = 0;
  long n = 0;
  int settle = 0;  // ms after each new target during which the chamber is still filling: not scored
  auto score = [&](double target) {
    return [&, target](double truth) {
      if (!std::isfinite(truth)) r.finite = false;
      r.saturated = r.saturated || rig.Saturated();
      if (settle > 0) {
        --settle;
        return;
      }
      const double e = truth - target;
      sum += e * e;
      ++n;
      r.max = std::max(r.max, std::fabs(e));
    };
  };
  rig.Follow(0, 400);
  settle = 1000;  // the first second after homing fills the chamber from vented
  switch (set) {
    case InputSet::kDemoStimuli: {
      // The demo's levels: outputs at 0, 10 and 30 kPa, two seconds each, in shuffled order.
      const double levels[] = {0, OutputAtShare(inverse, 0.1, max),
                               OutputAtShare(inverse, 0.3, max)};
      for (int k = 0; k < seconds / 2; ++k) {
        const double target = levels[rng() % 3];
        settle = 1000;
        rig.Follow(target, 2000, score(target));
      }
      break;
    }
    case InputSet::kBandLimitedRandom: {
      // Band-limited: five sines between 0.02 and 0.1 Hz with random phases, 10–90 % of the
      // range; a new target every 20 ms.
      std::uniform_real_distribution<double> phase(0, 2 * M_PI);
      double phases[5];
      for (double& p : phases) p = phase(rng);
      for (int k = 0; k < seconds * 50; ++k) {
        const double t = k * 0.02;
        double x = 0.5;
        for (int i = 0; i < 5; ++i)
          x += 0.08 * std::sin(2 * M_PI * (0.02 + 0.02 * i) * t + phases[i]);
        const double target = lo + (hi - lo) * std::clamp(x, 0.0, 1.0);
        rig.Follow(target, 20, score(target));
      }
      break;
    }
    case InputSet::kFastRamps: {
      // Triangles between 10 % and 90 % at 1 s per ramp: faster than the chamber settles.
      for (int k = 0; k < seconds * 50; ++k) {
        const double phase = std::fmod(k * 0.02, 2.0);
        const double target = lo + (hi - lo) * (phase < 1 ? phase : 2 - phase);
        rig.Follow(target, 20, score(target));
      }
      break;
    }
  }
  r.rms = n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0;
  return r;
}

}  // namespace palpa::testing
