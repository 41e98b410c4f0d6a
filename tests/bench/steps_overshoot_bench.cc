// Which random shaped steps of the jamming vacuum line overshoot, and why: the steps benchmark's
// random sequence (4 held-out units × 40 steps, 1 s dwells, shaped with the identified chamber),
// each step that overshoots by more than a threshold listed with when its overdrive ended, and
// with --trace the board's regulator and chamber models against the outlet the sensor reads and
// the true chamber through it (docs/performance.md, "Deep vacuum steps").
//   palpa_steps_overshoot_bench [THRESHOLD_PA] [--trace]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "steps_measure.h"
#include "steps_variants.h"

namespace pb = palpa::bench;
namespace ls = palpa::protocol::line_status;

int main(int argc, char** argv) {
  double threshold = 400;
  bool trace = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--trace") == 0)
      trace = true;
    else
      threshold = std::atof(argv[i]);
  }
  const pb::LineUnderTest l = pb::Lines()[1];
  const pb::Variant v = pb::Variants()[4];  // + shaping (identified chamber)
  std::vector<double> ratio, over;
  int beyond = 0;
  std::printf(
      "| unit | step | from → to (kPa) | overshoot (kPa) | at (ms) | overdrive until (ms) "
      "| saturated | settled (ms) | goal (ms) |\n|---|---|---|---:|---:|---:|---|---:|---:|\n");
  for (int u = 0; u < 4; ++u) {  // the steps benchmark's random sequence (RandomSteps)
    pb::RandomTargets targets(l, u);
    const auto session = v.Open(pb::RandomTargets::Unit(u));
    pb::RawLineSession& s = *session;
    l.Hold(s);
    double at = 0;
    for (int i = 0; i < 40; ++i) {
      const double to = targets.Next(at);
      s.Set({{l.line, static_cast<int32_t>(to)}});
      const double direction = to >= at ? 1 : -1, band = pb::Band(at, to);
      double worst = 0;
      int worst_ms = 0, last_outside = 0, shaped_until = 0;
      bool saturated = false;
      std::string lines;
      for (int ms = 1; ms <= 1000; ++ms) {
        s.Tick();
        const double chamber = s.Chamber(l.line);
        const palpa::core::LineState& board = s.LineStateOf(l.line);
        if (s.Status(l.line) & ls::kShaping) shaped_until = ms;
        saturated = saturated || (s.Status(l.line) & ls::kSaturated) != 0;
        if (direction * (chamber - to) > worst) worst = direction * (chamber - to), worst_ms = ms;
        if (std::fabs(chamber - to) > band) last_outside = ms;
        if (trace && ((ms <= 60 && ms % 4 == 0) || (ms <= 400 && ms % 20 == 0))) {
          char b[160];
          std::snprintf(b, sizeof(b), "| %d | %.1f | %.1f | %.1f | %.1f | %.1f |\n", ms,
                        s.Command(l.line) / 1e3, board.regulator_pa / 1e3, board.chamber_pa / 1e3,
                        s.Measured(l.line) / 1e3, chamber / 1e3);
          lines += b;
        }
      }
      const double goal = pb::GoalMs(pb::FastestMs(l.kind, at, to));
      ratio.push_back(last_outside >= 1000 ? pb::kNever : last_outside / goal);
      over.push_back(worst);
      if (worst > threshold) {
        ++beyond;
        std::printf("| %u | %d | %.1f → %.1f | %.2f | %d | %d | %s | %d | %.0f |\n",
                    pb::RandomTargets::Unit(u), i, at / 1e3, to / 1e3, worst / 1e3, worst_ms,
                    shaped_until, saturated ? "yes" : "no", last_outside, goal);
        if (trace)
          std::printf(
              "\n| ms | command | regulator model | chamber model | outlet (sensor) | "
              "chamber (true) |\n|---:|---:|---:|---:|---:|---:|\n%s\n",
              lines.c_str());
      }
      at = to;
    }
  }
  std::printf(
      "\n%d of %zu steps overshoot by more than %.1f kPa; p95 of settle ÷ goal %.2f, "
      "overshoot p95 %.2f kPa\n",
      beyond, over.size(), threshold / 1e3, pb::Quantile(ratio, 0.95),
      pb::Quantile(over, 0.95) / 1e3);
  return 0;
}
