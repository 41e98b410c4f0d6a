// Which random shaped steps of the jamming vacuum line overshoot, or miss their settling goal, and
// why: the steps benchmark's random sequence (4 held-out units × 40 steps, 1 s dwells, shaped with
// the identified chamber), each step that overshoots by more than a threshold (or, with --misses,
// settles later than its goal) listed with when its overdrive ended and the fastest step the
// unit's own regulator allows through its command, and with --trace the board's regulator and
// chamber models against the outlet the sensor reads and the true chamber through it
// (docs/performance.md, "Deep vacuum steps", "The random jamming steps' misses").
//   palpa_steps_overshoot_bench [THRESHOLD_PA] [--misses] [--trace]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "steps_bound.h"
#include "steps_measure.h"
#include "steps_variants.h"

namespace pb = palpa::bench;
namespace ls = palpa::protocol::line_status;

int main(int argc, char** argv) {
  double threshold = 400;
  bool trace = false, misses = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--trace") == 0)
      trace = true;
    else if (std::strcmp(argv[i], "--misses") == 0)
      misses = true;
    else
      threshold = std::atof(argv[i]);
  }
  const pb::LineUnderTest l = pb::Lines()[1];
  const pb::Variant v = pb::Variants()[4];  // + shaping (identified chamber)
  std::vector<double> ratio, over;
  int beyond = 0;
  // The listed steps' kinds: back toward atmosphere, with a 0.5 kPa band, out of the unit's reach
  // through its command (its regulator's alone, and with the dump valve open too).
  int toward_atmosphere = 0, narrow = 0, unreachable = 0, unreachable_dump = 0;
  std::printf(
      "| unit | step | from → to (kPa) | band (kPa) | overshoot (kPa) | at (ms) | overdrive until "
      "(ms) | saturated | settled (ms) | goal (ms) | fastest (ms) | through the command, this "
      "unit (ms) | … with the dump valve (ms) | last outside | steady error (kPa) |\n"
      "|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---|---:|\n");
  for (int u = 0; u < 4; ++u) {  // the steps benchmark's random sequence (RandomSteps)
    pb::RandomTargets targets(l, u);
    const auto session = v.Open(pb::RandomTargets::Unit(u));
    pb::RawLineSession& s = *session;
    l.Hold(s);
    double at = 0;
    for (int i = 0; i < 40; ++i) {
      const double to = targets.Next(at);
      const palpa::sim::RegulatorLine start = s.plant().regulator(l.line);
      s.Set({{l.line, static_cast<int32_t>(to)}});
      const double direction = to >= at ? 1 : -1, band = pb::Band(at, to);
      double worst = 0;
      int worst_ms = 0, last_outside = 0, shaped_until = 0;
      bool saturated = false, short_of = false;  // short of the target when last outside the band
      double tail = 0;
      std::string lines;
      for (int ms = 1; ms <= 1000; ++ms) {
        s.Tick();
        const double chamber = s.Chamber(l.line);
        const palpa::core::LineState& board = s.LineStateOf(l.line);
        if (s.Status(l.line) & ls::kShaping) shaped_until = ms;
        saturated = saturated || (s.Status(l.line) & ls::kSaturated) != 0;
        if (direction * (chamber - to) > worst) worst = direction * (chamber - to), worst_ms = ms;
        if (std::fabs(chamber - to) > band)
          last_outside = ms, short_of = direction * (chamber - to) < 0;
        if (ms > 800) tail += (chamber - to) / 200;
        if (trace && ((ms <= 60 && ms % 4 == 0) || (ms <= 400 && ms % 20 == 0))) {
          char b[160];
          std::snprintf(b, sizeof(b), "| %d | %.1f | %.1f | %.1f | %.1f | %.1f | %s |\n", ms,
                        s.Command(l.line) / 1e3, board.regulator_pa / 1e3, board.chamber_pa / 1e3,
                        s.Measured(l.line) / 1e3, chamber / 1e3,
                        (s.Vents() >> l.line & 1u) != 0 ? "open" : "");
          lines += b;
        }
      }
      const double fastest = pb::FastestMs(l.kind, at, to), goal = pb::GoalMs(fastest);
      ratio.push_back(last_outside >= 1000 ? pb::kNever : last_outside / goal);
      over.push_back(worst);
      if (misses ? last_outside > goal : worst > threshold) {
        ++beyond;
        const palpa::protocol::ConfigureLine& c = s.Config(l.line);
        const pb::CommandBound b =
            pb::FastestThroughCommand(start, at, to, c.limit_min_pa, c.limit_max_pa);
        const pb::CommandBound d =
            pb::FastestThroughCommand(start, at, to, c.limit_min_pa, c.limit_max_pa, true);
        const bool up = std::fabs(to) < std::fabs(at);
        toward_atmosphere += up;
        narrow += band <= 500;
        unreachable += b.settle_ms > goal;
        unreachable_dump += (up ? d.settle_ms : b.settle_ms) > goal;
        std::printf(
            "| %u | %d | %.1f → %.1f | %.2f | %.2f | %d | %d | %s | %d | %.0f | %.0f | %.0f | %s "
            "| %s | %.2f |\n",
            pb::RandomTargets::Unit(u), i, at / 1e3, to / 1e3, band / 1e3, worst / 1e3, worst_ms,
            shaped_until, saturated ? "yes" : "no", last_outside, goal, fastest,
            b.settle_ms == pb::kNever ? 1000.0 : b.settle_ms,
            up ? std::to_string(static_cast<int>(d.settle_ms == pb::kNever ? 1000 : d.settle_ms))
                     .c_str()
               : "—",
            short_of ? "short" : "beyond", tail / 1e3);
        if (trace)
          std::printf(
              "\n| ms | command | regulator model | chamber model | outlet (sensor) | "
              "chamber (true) | dump valve |\n|---:|---:|---:|---:|---:|---:|---|\n%s\n",
              lines.c_str());
      }
      at = to;
    }
  }
  if (misses)
    std::printf("\n%d of %zu steps settle later than their goal", beyond, over.size());
  else
    std::printf("\n%d of %zu steps overshoot by more than %.1f kPa", beyond, over.size(),
                threshold / 1e3);
  std::printf(
      ": %d back toward atmosphere, %d with a 0.5 kPa band, %d out of reach through the unit's "
      "command (%d with the dump valve); p95 of settle ÷ goal %.2f, overshoot p95 %.2f kPa\n",
      toward_atmosphere, narrow, unreachable, unreachable_dump, pb::Quantile(ratio, 0.95),
      pb::Quantile(over, 0.95) / 1e3);
  return 0;
}
