// Fast steps: the transitions and random sequences on held-out simulated units (plant
// level 3, virtual time), settling of the true chamber pressure to max(2 % of the step, 0.5 kPa)
// for good, overshoot and steady-state error, for each way of driving the line; against the
// plant's fastest step. Prints Markdown; with a docs directory, writes it and the charts there.
//   palpa_steps_bench [DOCS_DIR]
#include <cstdio>
#include <string>
#include <vector>

#include "doc_block.h"
#include "steps_measure.h"
#include "steps_stability.h"
#include "steps_variants.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;

namespace {

constexpr int kUnits = 12;        // held-out regulator and sensor units (seeds 101 …)
constexpr int kRandomUnits = 4;   // units the random sequences run on
constexpr int kRandomSteps = 40;  // per unit

struct Transition {
  double from_pa, to_pa;
};
const Transition kPneumatic[] = {
    {0, 10000}, {10000, 30000}, {30000, 10000}, {30000, 0}, {0, 80000}};
const Transition kVacuum[] = {
    {0, -10000}, {-10000, -30000}, {-30000, -10000}, {-30000, 0}, {0, -80000}};

int DwellMs(const pb::LineUnderTest& l, double from, double to) {
  return std::max(1500, static_cast<int>(3 * pb::FastestMs(l.kind, from, to)));
}

std::string Ms(double ms) {
  if (ms == pb::kNever) return "never";
  char b[32];
  std::snprintf(b, sizeof(b), "%.0f", ms);
  return b;
}

std::string Kpa(double pa) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.2f", pa / 1000);
  return b;
}

/// The named transitions on every held-out unit: one table row per transition.
std::string NamedRows(const pb::Variant& v, const pb::LineUnderTest& l, const Transition* t,
                      int count) {
  std::vector<std::vector<double>> settle(count), over(count), error(count);
  for (int u = 0; u < kUnits; ++u) {
    const auto session = v.Open(101 + u);
    pb::RawLineSession& s = *session;
    l.Hold(s);
    for (int i = 0; i < count; ++i) {
      s.Set({{l.line, static_cast<int32_t>(t[i].from_pa)}});
      for (int ms = 0; ms < DwellMs(l, 0, t[i].from_pa); ++ms) s.Tick();
      const pb::StepFigures f =
          pb::RunStep(s, l.line, t[i].from_pa, t[i].to_pa, DwellMs(l, t[i].from_pa, t[i].to_pa));
      settle[i].push_back(f.settle_ms);
      over[i].push_back(f.overshoot_pa);
      error[i].push_back(std::fabs(f.error_pa));
    }
  }
  std::string rows;
  for (int i = 0; i < count; ++i) {
    const double fastest = pb::FastestMs(l.kind, t[i].from_pa, t[i].to_pa);
    const double p95 = pb::Quantile(settle[i], 0.95);
    char b[256];
    std::snprintf(b, sizeof(b), "| %s → %s kPa | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                  Kpa(t[i].from_pa).c_str(), Kpa(t[i].to_pa).c_str(), v.name, Ms(fastest).c_str(),
                  Ms(pb::Quantile(settle[i], 0.5)).c_str(), Ms(p95).c_str(),
                  Ms(pb::GoalMs(fastest)).c_str(), p95 <= pb::GoalMs(fastest) ? "**met**" : "not",
                  Kpa(pb::Quantile(over[i], 0.95)).c_str(),
                  Kpa(pb::Quantile(error[i], 0.95)).c_str());
    rows += b;
  }
  return rows;
}

struct RandomFigures {
  double p50 = 0, p95 = 0, ratio95 = 0, within = 0, over95 = 0, error95 = 0, mean_abs = 0;
  int fell_back = 0;  ///< units whose line's shaped steps fell back to unshaped ones
};

/// Random steps (1 s dwells) for settling, then a random sequence with 0.5 s dwells for the mean
/// absolute chamber error.
RandomFigures RandomSteps(const pb::Variant& v, const pb::LineUnderTest& l) {
  std::vector<double> settle, ratio, over, error;
  double abs_sum = 0;
  int abs_n = 0, met = 0, fell_back = 0;
  for (int u = 0; u < kRandomUnits; ++u) {
    pb::RandomTargets targets(l, u);
    const auto session = v.Open(pb::RandomTargets::Unit(u));
    pb::RawLineSession& s = *session;
    l.Hold(s);
    double at = 0;
    for (int i = 0; i < 2 * kRandomSteps; ++i) {
      const double to = targets.Next(at);
      const bool dwell_half = i >= kRandomSteps;
      const pb::StepFigures f = pb::RunStep(s, l.line, at, to, dwell_half ? 500 : 1000);
      if (dwell_half) {
        abs_sum += f.abs_error_pa;
        ++abs_n;
      } else {
        const double goal = pb::GoalMs(pb::FastestMs(l.kind, at, to));
        settle.push_back(f.settle_ms);
        ratio.push_back(f.settle_ms / goal);
        met += f.settle_ms <= goal;
        over.push_back(f.overshoot_pa);
        error.push_back(std::fabs(f.error_pa));
      }
      at = to;
    }
    fell_back += s.ShapingFellBack(l.line);
  }
  return {pb::Quantile(settle, 0.5), pb::Quantile(settle, 0.95),
          pb::Quantile(ratio, 0.95), 100.0 * met / static_cast<double>(settle.size()),
          pb::Quantile(over, 0.95),  pb::Quantile(error, 0.95),
          abs_sum / abs_n,           fell_back};
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<pb::Variant> variants = pb::Variants();
  std::string named =
      "| step | driven by | fastest (ms) | p50 (ms) | p95 (ms) | goal (ms) | goal met | "
      "overshoot p95 (kPa) | steady-state \\|error\\| p95 (kPa) |\n"
      "|---|---|---:|---:|---:|---:|---|---:|---:|\n";
  std::string random =
      "| line | driven by | p50 (ms) | p95 (ms) | p95 of settle ÷ goal | within goal | "
      "overshoot p95 (kPa) | steady-state \\|error\\| p95 (kPa) | mean \\|error\\|, 0.5 s dwells "
      "(kPa) | units fallen back to unshaped "
      "|\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::vector<pb::ChartPoint> points;
  for (const pb::LineUnderTest& l : pb::Lines()) {
    const bool vacuum = l.kind == pp::LineKind::kVacuum;
    for (const pb::Variant& v : variants) {
      if (v.named) named += NamedRows(v, l, vacuum ? kVacuum : kPneumatic, 5);
      const RandomFigures r = RandomSteps(v, l);
      char b[320];
      std::snprintf(b, sizeof(b),
                    "| %s | %s | %s | %s | %.2f | %.0f %% | %s | %s | %s | %d of %d |\n", l.name,
                    v.name, Ms(r.p50).c_str(), Ms(r.p95).c_str(), r.ratio95, r.within,
                    Kpa(r.over95).c_str(), Kpa(r.error95).c_str(), Kpa(r.mean_abs).c_str(),
                    r.fell_back, kRandomUnits);
      random += b;
      points.push_back({l.name, v.name, r.p95, r.over95 / 1000});
    }
  }
  const std::string block = "Named transitions, " + std::to_string(kUnits) +
                            " held-out units each:\n\n" + named + "\nRandom steps, " +
                            std::to_string(kRandomUnits) + " held-out units × " +
                            std::to_string(kRandomSteps) + " steps:\n\n" + random;
  std::printf("%s", block.c_str());
  std::vector<uint32_t> units;
  std::vector<uint32_t> held_out;  // units no choice of the identification step looked at
  for (uint32_t u = 0; u < kUnits; ++u) {
    units.push_back(101 + u);
    held_out.push_back(401 + u);
  }
  const std::string fit = pb::ChamberFitTable(units, held_out);
  std::printf("\n%s", fit.c_str());
  // The jamming line's deep step settles to a pascal within 2 s behind the tube.
  const std::string tube = pb::ChamberFitTable(units, held_out, true, 2.0);
  std::printf("\n%s", tube.c_str());
  std::string map;
  for (const pb::LineUnderTest& l : pb::Lines())
    map += (map.empty() ? "" : "\n") + pb::StabilityMap(l);
  std::printf("\n%s", map.c_str());
  if (argc > 1) {
    const std::string docs = argv[1];
    if (!pb::ReplaceBlock(docs + "/performance.md", "steps", block) ||
        !pb::ReplaceBlock(docs + "/performance.md", "steps-fit", fit) ||
        !pb::ReplaceBlock(docs + "/performance.md", "steps-fit-tube", tube) ||
        !pb::ReplaceBlock(docs + "/performance.md", "steps-map", map)) {
      std::fprintf(stderr, "cannot write the steps blocks into %s/performance.md\n", docs.c_str());
      return 1;
    }
    if (!pb::WriteCharts(docs, points)) return 1;
  }
  return 0;
}
