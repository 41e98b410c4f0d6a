// The thesis grid and the adaptive protocol for a jamming finger's stiffness map.
#include "palpa/calibration/map_protocols.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace palpa::calibration {
namespace {

using nlohmann::json;

json PressJson(const MapPress& p) {
  return {p.bias_kpa,     p.vacuum_kpa, p.measured_bias_kpa, p.measured_vacuum_kpa, p.stiffness,
          p.loop_area_mj, p.r2,         p.residual_n,        p.free_force_n,        p.readings,
          p.time_s};
}

MapPress PressFrom(const json& j) {
  MapPress p;
  p.bias_kpa = j[0].get<double>();
  p.vacuum_kpa = j[1].get<double>();
  p.measured_bias_kpa = j[2].get<double>();
  p.measured_vacuum_kpa = j[3].get<double>();
  p.stiffness = j[4].get<double>();
  p.loop_area_mj = j[5].get<double>();
  p.r2 = j[6].get<double>();
  p.residual_n = j[7].get<double>();
  p.free_force_n = j[8].get<double>();
  p.readings = j[9].get<int>();
  p.time_s = j[10].get<double>();
  return p;
}

std::vector<MapPress> PressesFrom(const json& state) {
  std::vector<MapPress> out;
  if (state.contains("presses")) {
    for (const json& j : state["presses"]) out.push_back(PressFrom(j));
  }
  return out;
}

void Append(json& state, const std::vector<MapPress>& presses) {
  if (!state.contains("presses")) state["presses"] = json::array();
  for (const MapPress& p : presses) state["presses"].push_back(PressJson(p));
}

std::string Kpa(double v) { return std::to_string(static_cast<int>(std::lround(v))); }

/// Mean and population spread.
std::pair<double, double> MeanSpread(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x / static_cast<double>(v.size());
  for (double x : v) s += (x - m) * (x - m) / static_cast<double>(v.size());
  return {m, std::sqrt(s)};
}

}  // namespace

std::vector<MapSample> StiffnessSamples(const std::vector<MapPress>& presses) {
  std::vector<MapSample> out;
  for (const MapPress& p : presses) out.push_back({p.bias_kpa, p.vacuum_kpa, p.stiffness});
  return out;
}

MapEstimate EstimateMap(const std::vector<MapPress>& presses, const MapBox& box) {
  return EstimateMap(presses, StiffnessSurface(StiffnessSamples(presses), box));
}

MapEstimate EstimateMap(const std::vector<MapPress>& presses, const StiffnessSurface& surface) {
  MapEstimate e;
  e.cycles = static_cast<int>(presses.size());
  std::map<std::pair<double, double>, std::vector<double>> by_condition;
  for (const MapPress& p : presses) by_condition[{p.bias_kpa, p.vacuum_kpa}].push_back(p.stiffness);
  e.conditions = static_cast<int>(by_condition.size());
  // Pooled within-condition spread, relative to each condition's mean.
  double squares = 0;
  int freedom = 0;
  for (const auto& [at, k] : by_condition) {
    if (k.size() < 2) continue;
    ++e.repeated_conditions;
    double mean = 0;
    for (double x : k) mean += x / static_cast<double>(k.size());
    for (double x : k) squares += (x - mean) * (x - mean) / (mean * mean);
    freedom += static_cast<int>(k.size()) - 1;
  }
  e.press_noise = freedom > 0 ? std::sqrt(squares / freedom) : 0;
  if (!surface.ok()) return e;
  e.cv_error = surface.CrossValidatedError();
  // A held-out press misses by the map's error and its own noise together.
  e.map_error = std::sqrt(std::max(0.0, e.cv_error * e.cv_error - e.press_noise * e.press_noise));
  return e;
}

std::vector<ConditionSummary> SummariseConditions(const std::vector<MapPress>& presses) {
  std::vector<std::pair<double, double>> order;
  std::map<std::pair<double, double>, std::vector<const MapPress*>> by_condition;
  for (const MapPress& p : presses) {
    auto& list = by_condition[{p.bias_kpa, p.vacuum_kpa}];
    if (list.empty()) order.push_back({p.bias_kpa, p.vacuum_kpa});
    list.push_back(&p);
  }
  std::vector<ConditionSummary> out;
  for (const auto& at : order) {
    const auto& list = by_condition[at];
    const double n = static_cast<double>(list.size());
    ConditionSummary g{at.first, at.second, static_cast<int>(list.size()), 0, 0, 0, 1};
    for (const MapPress* p : list) {
      g.stiffness_mean += p->stiffness / n;
      g.loop_area_mean += p->loop_area_mj / n;
      g.r2_min = std::min(g.r2_min, std::clamp(p->r2, 0.0, 1.0));
    }
    for (const MapPress* p : list) {
      g.stiffness_spread +=
          (p->stiffness - g.stiffness_mean) * (p->stiffness - g.stiffness_mean) / n;
    }
    g.stiffness_spread = std::sqrt(g.stiffness_spread);
    out.push_back(g);
  }
  return out;
}

host::GridPoint FileGridPoint(const ConditionSummary& c) {
  return host::GridPoint{
      1000 * c.bias_kpa,         1000 * c.vacuum_kpa, c.cycles, 1000 * c.stiffness_mean,
      1000 * c.stiffness_spread, c.loop_area_mean,    c.r2_min};
}

double RecommendBias(const std::vector<ConditionSummary>& grid) {
  // "Kept" allows for what a few presses resolve: a bias may lose a fifth of the widest range.
  constexpr double kRangeKept = 0.8;
  std::map<double, std::pair<double, double>> range;  // bias → (min, max) stiffness
  std::map<double, std::vector<double>> loops;
  for (const ConditionSummary& g : grid) {
    auto& r = range.try_emplace(g.bias_kpa, 1e9, -1e9).first->second;
    r.first = std::min(r.first, g.stiffness_mean);
    r.second = std::max(r.second, g.stiffness_mean);
    loops[g.bias_kpa].push_back(g.loop_area_mean);
  }
  double widest = 0;
  for (const auto& [bias, r] : range) widest = std::max(widest, r.second - r.first);
  double best = range.empty() ? 0 : range.begin()->first, least = 1e300;
  for (const auto& [bias, r] : range) {
    if (r.second - r.first < kRangeKept * widest) continue;
    const double loop = MeanSpread(loops[bias]).first;
    if (loop < least) {
      least = loop;
      best = bias;
    }
  }
  return best;
}

double RecommendBiasFromMap(const std::vector<MapPress>& presses, const MapBox& box) {
  std::vector<MapSample> loops;
  for (const MapPress& p : presses) loops.push_back({p.bias_kpa, p.vacuum_kpa, p.loop_area_mj});
  const StiffnessSurface stiffness(StiffnessSamples(presses), box), loop(loops, box);
  std::vector<ConditionSummary> lattice;
  for (const MapSample& c : Lattice(box, 9, 11)) {
    ConditionSummary g;
    g.bias_kpa = c.bias_kpa;
    g.vacuum_kpa = c.vacuum_kpa;
    g.stiffness_mean = stiffness.Predict(c.bias_kpa, c.vacuum_kpa).mean;
    g.loop_area_mean = loop.Predict(c.bias_kpa, c.vacuum_kpa).mean;
    lattice.push_back(g);
  }
  return RecommendBias(lattice);
}

RigStatus PressAt(Rig& rig, uint8_t finger, double zero_mm, double bias_kpa, double vacuum_kpa,
                  int repeats, const PressSettings& press, std::vector<MapPress>* out,
                  std::vector<PressCycle>* cycles) {
  RigStatus s = rig.board.SetDrive(finger, bias_kpa, vacuum_kpa);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  rig.time.Wait(press.dwell_s);
  MapPress m;
  m.bias_kpa = bias_kpa;
  m.vacuum_kpa = vacuum_kpa;
  const size_t first = out->size();
  for (int r = 0; r < repeats; ++r) {
    m.time_s = rig.time.Now();
    PressCycle cycle;
    s = Press(rig, zero_mm, press.depth_mm, press.speed_mm_s, &cycle);
    if (!s.ok()) return s;
    m.stiffness = cycle.stiffness_n_per_mm;
    m.loop_area_mj = cycle.loop_area_mj;
    m.r2 = cycle.r2;
    m.residual_n = cycle.residual_n;
    m.free_force_n = cycle.free_force_n;
    m.readings = static_cast<int>(cycle.loading.size());
    out->push_back(m);
    if (cycles != nullptr) cycles->push_back(std::move(cycle));
  }
  // What the lines hold after the presses, long settled: the leak check's trim-on reading.
  double bias = 0, vacuum = 0;
  s = rig.board.MeasuredKpa(rig.board.bias_line(finger), &bias);
  if (s.ok()) s = rig.board.MeasuredKpa(rig.board.driven_line(finger), &vacuum);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  for (size_t i = first; i < out->size(); ++i) {
    (*out)[i].measured_bias_kpa = bias;
    (*out)[i].measured_vacuum_kpa = vacuum;
  }
  // Vacuum released: the next condition is approached from rest, and the pump rests inside its
  // run-time limit.
  s = rig.board.SetDrive(finger, bias_kpa, 0);
  if (!s.ok()) return AbortSafe(rig, s.status, "board: " + s.message);
  rig.time.Wait(press.dwell_s);
  return {};
}

RigStatus RunGridMap(Rig& rig, uint8_t finger, double zero_mm, const PressSettings& press,
                     const std::vector<double>& biases_kpa, const std::vector<double>& vacuums_kpa,
                     int repeats, json& state, const MapHooks& hooks,
                     std::vector<MapPress>* presses, std::vector<PressCycle>* cycles) {
  if (!state.is_object()) state = json::object();
  *presses = PressesFrom(state);
  const size_t finished = state.value("grid_done", size_t{0});
  size_t index = 0;
  for (double b : biases_kpa) {
    for (double v : vacuums_kpa) {
      if (index++ < finished) {
        if (hooks.done) hooks.done();
        continue;
      }
      if (hooks.step)
        hooks.step("indentation grid: bias " + Kpa(b) + " kPa, vacuum " + Kpa(v) + " kPa");
      std::vector<MapPress> taken;
      RigStatus s = PressAt(rig, finger, zero_mm, b, v, repeats, press, &taken, cycles);
      if (!s.ok()) return s;
      Append(state, taken);
      state["grid_done"] = index;
      presses->insert(presses->end(), taken.begin(), taken.end());
      if (hooks.after_press) hooks.after_press(*presses);
      if (hooks.done) hooks.done();
    }
  }
  return {};
}

RigStatus RunAdaptiveMap(Rig& rig, uint8_t finger, double zero_mm, const PressSettings& press,
                         const AdaptiveOptions& o, json& state, const MapHooks& hooks,
                         std::vector<MapPress>* presses, MapEstimate* estimate,
                         std::vector<PressCycle>* cycles) {
  if (!state.is_object()) state = json::object();
  *presses = PressesFrom(state);
  for (size_t i = 0; i < presses->size(); ++i) {
    if (hooks.done) hooks.done();
  }
  const MapBox& box = o.box;
  const std::vector<MapSample> start = {{0, 0, 0},
                                        {box.bias_max_kpa, 0, 0},
                                        {0, -box.vacuum_max_kpa, 0},
                                        {box.bias_max_kpa, -box.vacuum_max_kpa, 0},
                                        {box.bias_max_kpa / 2, -box.vacuum_max_kpa / 2, 0}};
  const std::vector<MapSample> candidates = Lattice(box, o.bias_steps, o.vacuum_steps);
  for (;;) {
    const int taken = static_cast<int>(presses->size());
    MapSample next{};
    const StiffnessSurface surface(StiffnessSamples(*presses), box);  // fitted once per cycle
    *estimate = EstimateMap(*presses, surface);
    if (taken < static_cast<int>(start.size())) {
      next = start[static_cast<size_t>(taken)];
    } else {
      if (taken >= o.max_cycles) return {};
      if (taken >= o.min_cycles && estimate->repeated_conditions > 0 &&
          estimate->map_error <= o.target_error) {
        return {};
      }
      // Without a repeat the noise is unknown and the estimate is all error: learn it once.
      next = taken >= o.min_cycles - 1 && estimate->repeated_conditions == 0
                 ? surface.WorstPredicted()
                 : NextCondition(surface, candidates);
    }
    if (hooks.step) {
      hooks.step("adaptive map, cycle " + std::to_string(taken + 1) + ": bias " +
                 Kpa(next.bias_kpa) + " kPa, vacuum " + Kpa(next.vacuum_kpa) + " kPa");
    }
    std::vector<MapPress> one;
    RigStatus s =
        PressAt(rig, finger, zero_mm, next.bias_kpa, next.vacuum_kpa, 1, press, &one, cycles);
    if (!s.ok()) return s;
    Append(state, one);
    presses->push_back(one.front());
    if (hooks.after_press) hooks.after_press(*presses);
    if (hooks.done) hooks.done();
  }
}

}  // namespace palpa::calibration
