// Regulator: static map with play, dead time, the pilot stage's lag; the line behind it flows
// (line_flow.cc). Float only.
#include "palpa/hal/sim/regulator_line.h"

#include <algorithm>

#include "palpa/hal/sim/plant_params.h"

namespace palpa::sim {
namespace p = params;
namespace {

constexpr float kPi = 3.14159265f;
constexpr float kLitresPerMinute = 1.0f / 60000.0f;  // → m³/s
constexpr float kMillilitre = 1e-6f;                 // → m³

}  // namespace

RegulatorSetup NominalRegulatorSetup(protocol::LineKind kind, FlowAssumptions a) {
  RegulatorSetup s;
  const bool vacuum = kind == protocol::LineKind::kVacuum;
  s.sign = vacuum ? -1.0f : 1.0f;
  s.full_scale_pa = p::kRegulatorFullScalePa;
  s.min_set_pa = p::kRegulatorMinSetPa;
  s.lag_tau_s = p::kRegulatorLagTauS;
  s.dead_time_s = p::kRegulatorDeadTimeS;
  LineFlowSetup& f = s.flow;
  const float atm = p::kFlowAtmospherePa;
  f.sign = s.sign;
  f.atmosphere_pa = atm;
  f.critical_ratio = p::kFlowCriticalRatio;
  f.band_pa = p::kFlowValveBandPa * a.band;
  // Conductances from the full flows: the pressure class choked from its supply into an outlet
  // at atmosphere, the vacuum class choked from an outlet at atmosphere into the pump.
  if (vacuum) {
    f.supply_abs_pa = p::kFlowPumpAbsPa;
    f.main_conductance = a.flow * p::kFlowVacuumFlowLMinAnr * kLitresPerMinute / atm;
  } else {
    f.supply_abs_pa = p::kFlowSupplyPa + atm;
    f.main_conductance =
        a.flow * p::kFlowPressureFlowLMinAnr * kLitresPerMinute /
        (f.supply_abs_pa * OrificeFlowFactor(atm / f.supply_abs_pa, f.critical_ratio));
  }
  f.exhaust_conductance = f.main_conductance * p::kFlowExhaustShare;
  const float dump_from = atm + 100000.0f;
  f.dump_conductance = a.flow * p::kFlowDumpFlowLMinAnr * kLitresPerMinute /
                       (dump_from * OrificeFlowFactor(atm / dump_from, f.critical_ratio));
  const float bore_m = 1e-3f * (vacuum ? p::kLineVacuumBoreMm : p::kLinePressureBoreMm);
  const float r = 0.5f * bore_m;
  const float length = p::kLineLengthM * a.tube;
  const float tube_volume = kPi * r * r * length;
  f.tube_conductance = kPi * r * r * r * r / (8.0f * p::kFlowAirViscosityPaS * length);
  const float chamber_ml = vacuum                              ? p::kLineJammingChamberMl
                           : kind == protocol::LineKind::kBias ? p::kLineBiasChamberMl
                                                               : p::kLinePneumaticChamberMl;
  f.outlet_volume_m3 = p::kLineRegulatorOutletMl * kMillilitre + 0.5f * tube_volume;
  f.chamber_volume_m3 = chamber_ml * a.chamber * kMillilitre + 0.5f * tube_volume;
  return s;
}

RegulatorLine::RegulatorLine(const RegulatorSetup& setup, float step_s)
    : setup_(setup), flow_(setup.flow, step_s) {
  lag_alpha_ = setup.lag_tau_s > 0 ? step_s / (setup.lag_tau_s + step_s) : 1.0f;
  const float steps = step_s > 0 ? setup.dead_time_s / step_s + 0.5f : 0.0f;
  delay_steps_ =
      static_cast<uint8_t>(steps >= kMaxRegulatorDelaySteps ? kMaxRegulatorDelaySteps - 1 : steps);
}

float RegulatorLine::StaticOutput(float magnitude) const {
  const RegulatorErrors& e = setup_.errors;
  const float fs = setup_.full_scale_pa;
  const float x = std::clamp(magnitude / fs, 0.0f, 1.0f);
  // Linearity error: a bow, zero at both ends, largest mid-scale (4x(1-x) peaks at 1).
  const float bow = e.linearity_pa * 4.0f * x * (1.0f - x);
  return std::clamp((1.0f + e.gain) * magnitude + e.offset_pa + bow, 0.0f, fs);
}

void RegulatorLine::Step(float command_pa, bool vented, bool dump_open) {
  if (vented) {
    // The supply is shut and the dump valve open; the regulator's pilot decays with its command.
    pilot_ += lag_alpha_ * (0.0f - pilot_);
    for (float& d : delay_) d = 0;
    if (setup_.dynamics) {
      flow_.Step(pilot_, true);
      outlet_ = flow_.outlet_pa();
      chamber_ = flow_.chamber_pa();
    } else {
      outlet_ = chamber_ = 0;
    }
    return;
  }
  // The regulator only makes pressure of its own sign; a command the other way means 0.
  const float magnitude = std::clamp(command_pa * setup_.sign, 0.0f, setup_.full_scale_pa);
  // Hysteresis and sensitivity: the command must move past the play before the output follows.
  const float r = setup_.errors.play_pa;
  if (magnitude > play_ + r) play_ = magnitude - r;
  if (magnitude < play_ - r) play_ = magnitude + r;
  float target = magnitude < setup_.min_set_pa ? 0.0f : StaticOutput(play_ < 0 ? 0 : play_);
  target *= setup_.sign;
  if (!setup_.dynamics) {
    pilot_ = outlet_ = chamber_ = dump_open ? 0.0f : target;
    return;
  }
  float delayed = target;
  if (delay_steps_ > 0) {
    delayed = delay_[delay_index_];
    delay_[delay_index_] = target;
    delay_index_ = static_cast<uint8_t>((delay_index_ + 1) % delay_steps_);
  }
  pilot_ += lag_alpha_ * (delayed - pilot_);
  flow_.Step(pilot_, false, dump_open);
  outlet_ = flow_.outlet_pa();
  chamber_ = flow_.chamber_pa();
}

}  // namespace palpa::sim
