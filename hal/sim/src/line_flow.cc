// A line's air path: valve flows (ISO 6358), a laminar tube, two volumes; explicit sub-steps
// short enough for the stiffest of them. Float only, absolute pressures inside.
#include "palpa/hal/sim/line_flow.h"

#include <algorithm>

namespace palpa::sim {
namespace {

float Max(float a, float b) { return a > b ? a : b; }

/// The last stretch of the flow function that is linear (a fraction of the pressure ratio).
constexpr float kLinearStretch = 0.005f;
/// φ's slope over that stretch, per unit ratio, bounds how stiff a valve is near equilibrium.
constexpr float kSteepestFactor = 26.0f;

/// ANR flow through a valve of conductance `c` from the side at `from` to the side at `to`
/// (absolute Pa); negative when the air goes the other way.
float Orifice(float c, float from, float to, float b) {
  if (c <= 0 || from == to) return 0;
  if (from > to) return c * from * OrificeFlowFactor(to / from, b);
  return -c * to * OrificeFlowFactor(from / to, b);
}

}  // namespace

float OrificeFlowFactor(float ratio, float critical_ratio) {
  const float b = std::clamp(critical_ratio, 0.0f, 0.95f);
  auto elliptic = [b](float r) {
    const float x = (r - b) / (1.0f - b);
    return __builtin_sqrtf(Max(0.0f, 1.0f - x * x));
  };
  const float r = std::clamp(ratio, 0.0f, 1.0f);
  if (r <= b) return 1.0f;
  const float knee = 1.0f - kLinearStretch;
  if (r < knee) return elliptic(r);
  return elliptic(knee) * (1.0f - r) / kLinearStretch;
}

LineFlow::LineFlow(const LineFlowSetup& setup, float step_s) : setup_(setup) {
  const float atm = setup.atmosphere_pa;
  const float top = Max(setup.supply_abs_pa, atm);
  const float outlet_v = setup.tube_conductance > 0
                             ? setup.outlet_volume_m3
                             : setup.outlet_volume_m3 + setup.chamber_volume_m3;
  // The valves are stepped explicitly: the fastest rate (1/s) of the outlet volume through them
  // comes from their proportional band and the steepest part of their flow function. A step of
  // that rate's inverse neither rings nor diverges. The tube and the leak are stepped
  // implicitly (they are stiff where the chamber is small), so they set no bound.
  const float valves = setup.main_conductance + setup.exhaust_conductance + setup.dump_conductance;
  const float rate = atm * valves * (top / Max(setup.band_pa, 1.0f) + kSteepestFactor) / outlet_v;
  const float n = step_s * rate + 1.0f;
  sub_steps_ = static_cast<uint8_t>(n > 200.0f ? 200.0f : n);
  sub_step_s_ = step_s / static_cast<float>(sub_steps_);
  Preset(0);
}

void LineFlow::Preset(float pa) {
  outlet_ = chamber_ = Max(0.0f, pa + setup_.atmosphere_pa);
  regulator_flow_ = 0;
}

float LineFlow::Opening(float pilot_pa) const {
  return std::clamp(setup_.sign * (pilot_pa - outlet_pa()) / setup_.band_pa, -1.0f, 1.0f);
}

void LineFlow::Step(float pilot_pa, bool vented, bool dump_open) {
  for (uint8_t i = 0; i < sub_steps_; ++i)
    Advance(vented ? 0.0f : Opening(pilot_pa), vented || dump_open);
}

void LineFlow::StepOpen(float opening) {
  for (uint8_t i = 0; i < sub_steps_; ++i) Advance(std::clamp(opening, -1.0f, 1.0f), false);
}

float LineFlow::ValveFlow(float opening) const {
  const float b = setup_.critical_ratio;
  if (opening > 0)  // towards the supply's pressure: filled from it, or evacuated to the pump
    return opening * Orifice(setup_.main_conductance, setup_.supply_abs_pa, outlet_, b);
  // Back towards atmosphere: exhausted (pressure) or let in (vacuum).
  return -opening * Orifice(setup_.exhaust_conductance, setup_.atmosphere_pa, outlet_, b);
}

void LineFlow::Advance(float opening, bool dump_open) {
  const float atm = setup_.atmosphere_pa;
  const float b = setup_.critical_ratio;
  regulator_flow_ = ValveFlow(opening);
  float into_outlet = regulator_flow_;
  if (dump_open) into_outlet += Orifice(setup_.dump_conductance, atm, outlet_, b);
  const float dt = sub_step_s_;
  if (setup_.tube_conductance <= 0) {  // one volume: leak through the dump valve's conductance
    into_outlet -= leak_ * Orifice(setup_.dump_conductance, outlet_, atm, b);
    outlet_ = Max(0.0f, outlet_ + dt * atm * into_outlet /
                                      (setup_.outlet_volume_m3 + setup_.chamber_volume_m3));
    chamber_ = outlet_;
    return;
  }
  outlet_ = Max(0.0f, outlet_ + dt * atm * into_outlet / setup_.outlet_volume_m3);
  // The tube, backward Euler linearised in the pressures' sum: the air moved, m (Pa·m³), makes
  // the difference it leaves drive it, m = dt·c·(Δ − m·(1/V_o + 1/V_c)); the air is conserved.
  const float vo = setup_.outlet_volume_m3, vc = setup_.chamber_volume_m3;
  const float c = 0.5f * setup_.tube_conductance * (outlet_ + chamber_);
  const float moved = dt * c * (outlet_ - chamber_) / (1.0f + dt * c * (1.0f / vo + 1.0f / vc));
  outlet_ -= moved / vo;
  chamber_ += moved / vc;
  // The leak the same way, towards atmosphere.
  if (leak_ > 0) {
    const float cl = 0.5f * leak_ * setup_.tube_conductance * (chamber_ + atm);
    chamber_ = atm + (chamber_ - atm) / (1.0f + dt * cl / vc);
  }
}

}  // namespace palpa::sim
