// The in-process calibration rig.
#include "sim_rig.h"

#include <algorithm>
#include <cmath>

namespace palpa::testing {
namespace pp = protocol;
using calibration::RigStatus;

SimRig::SimRig(const SimRigOptions& options)
    : board_(PlantBoardOptions(options.config, options.unit, options.seed, options.effects)),
      finger_(options.finger),
      noise_rng_(options.seed * 31u + 7u) {
  model_ = std::make_unique<sim::RigModel>(board_.sim().plant(), options.finger,
                                           options.seed * 17u + 5u);
  board_.sim().OnStep([this](uint64_t) {
    model_->Step(0.001f);
    peak_force_n = std::max(peak_force_n, model_->true_force_n());
  });
  configured_ = board_.config().lines;
  for (uint8_t f = 0; f < board_.config().finger_count; ++f)
    board_.Send(pp::SetFingerMode{f, pp::FingerMode::kRaw});
  board_.Run(5);
}

void SimRig::Wait(double seconds) {
  board_.Run(std::max(1, static_cast<int>(std::lround(seconds * 1000))));
}

RigStatus SimRig::MoveTo(double mm, double speed_mm_s) {
  if (stage_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no answer from the stage");
  model_->StopOnForce(0);
  model_->stage().MoveTo(static_cast<float>(mm), static_cast<float>(speed_mm_s));
  return {};
}

RigStatus SimRig::MoveUntilForce(double mm, double speed_mm_s, double stop_n) {
  if (!force_stop) return Stage::MoveUntilForce(mm, speed_mm_s, stop_n);
  if (stage_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no answer from the stage");
  model_->StopOnForce(static_cast<float>(stop_n));
  model_->stage().MoveTo(static_cast<float>(mm), static_cast<float>(speed_mm_s));
  return {};
}

RigStatus SimRig::Position(double* mm) {
  if (stage_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no answer from the stage");
  *mm = model_->PositionMm();
  return {};
}

RigStatus SimRig::Moving(bool* moving) {
  if (stage_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no answer from the stage");
  *moving = model_->stage().moving();
  return {};
}

RigStatus SimRig::Stop() {
  model_->StopOnForce(0);
  model_->stage().MoveTo(model_->stage().position_mm(), 1.0f);
  return {};
}

RigStatus SimRig::Read(double* newtons) {
  if (force_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no data from the force sensor");
  *newtons = model_->ReadForceN() + force_drift_n_per_s * (Now() - tared_at_s_);
  if (force_extra_noise_n > 0) {
    *newtons += std::normal_distribution<double>(0, force_extra_noise_n)(noise_rng_);
  }
  if (force_latency_s > 0) Wait(force_latency_s);  // the reading arrives late, the stage moves on
  return {};
}

RigStatus SimRig::Tare() {
  if (force_lost) return RigStatus::Fail(pp::Status::kUnavailable, "no data from the force sensor");
  model_->Tare();
  tared_at_s_ = Now();
  return {};
}

void SimRig::ScaleActuator(float factor) {
  sim::Plant& plant = board_.sim().plant();
  if (sim::JammingActuator* j = plant.jamming(finger_)) j->ScaleUnit(factor);
  if (sim::PneumaticActuator* p = plant.pneumatic(finger_)) p->ScaleUnit(factor);
}

bool SimRig::jamming(uint8_t finger) {
  return board_.config().fingers[finger].kind == pp::FingerKind::kJamming;
}

uint8_t SimRig::driven_line(uint8_t finger) {
  const pp::ConfigureFinger& f = board_.config().fingers[finger];
  return f.kind == pp::FingerKind::kJamming ? f.line_b : f.line_a;
}

RigStatus SimRig::SetDrive(uint8_t finger, double kpa_a, double kpa_b) {
  const pp::ConfigureFinger& f = board_.config().fingers[finger];
  pp::SetLineSetpoints sp{};
  sp.session = InProcessBoard::kSession;
  sp.generation = board_.next_generation();
  sp.entries[sp.entry_count++] = {f.line_a, static_cast<int32_t>(std::lround(kpa_a * 1000))};
  if (f.line_b != pp::kNoLine)
    sp.entries[sp.entry_count++] = {f.line_b, static_cast<int32_t>(std::lround(kpa_b * 1000))};
  board_.Send(sp);
  return {};
}

RigStatus SimRig::MeasuredKpa(uint8_t line, double* kpa) {
  *kpa = board_.SensorPa(line) / 1000.0;
  return {};
}

RigStatus SimRig::LineRangeKpa(uint8_t line, double* kpa) {
  const pp::ConfigureLine& c = board_.config().lines[line];
  *kpa = std::max(std::abs(c.limit_min_pa), std::abs(c.limit_max_pa)) / 1000.0;
  return {};
}

RigStatus SimRig::SetTrim(uint8_t line, bool on) {
  pp::ConfigureLine c = board_.config().lines[line];
  c.trim_kp = on ? configured_[line].trim_kp : 0.0f;
  c.trim_ki_per_s = on ? configured_[line].trim_ki_per_s : 0.0f;
  board_.SendConfig(c);
  board_.Run(2);
  return board_.config().lines[line].trim_kp == c.trim_kp
             ? RigStatus{}
             : RigStatus::Fail(pp::Status::kBadValue, "the board refused the trim change");
}

RigStatus SimRig::SetBareLine(uint8_t line, bool bare) {
  pp::ConfigureLine c = configured_[line];
  if (bare) calibration::MakeBare(c);
  board_.SendConfig(c);
  board_.Run(2);
  return board_.config().lines[line].slew_pa_per_s == c.slew_pa_per_s
             ? RigStatus{}
             : RigStatus::Fail(pp::Status::kBadValue, "the board refused the line's change");
}

RigStatus SimRig::Faults(uint32_t* bitmap) {
  *bitmap = board_.sim().board().latched_faults();
  return {};
}

RigStatus SimRig::VentAll() {
  pp::SetLineSetpoints sp{};
  sp.session = InProcessBoard::kSession;
  sp.generation = board_.next_generation();
  for (uint8_t i = 0; i < board_.config().line_count; ++i) sp.entries[sp.entry_count++] = {i, 0};
  board_.Send(sp);
  return {};
}

std::vector<std::pair<double, double>> TrueChamberStep(
    const SimRigOptions& options, double from_kpa, double to_kpa,
    std::vector<std::pair<double, double>>* outlet, double after_s) {
  SimRig sim(options);
  const uint8_t finger = options.finger, line = sim.driven_line(finger);
  const bool jamming = sim.jamming(finger);
  sim.SetBareLine(line, true);
  auto drive = [&](double kpa) {
    jamming ? sim.SetDrive(finger, 20, -kpa) : sim.SetDrive(finger, kpa, 0);
  };
  drive(from_kpa);
  sim.Wait(1.0);
  std::vector<std::pair<double, double>> samples;
  if (outlet) outlet->clear();
  const auto& regulator = sim.board().sim().plant().regulator(line);
  for (int i = -100; i < std::lround(after_s * 1000); ++i) {
    if (i == 0) drive(to_kpa);
    samples.push_back({i * 0.001, regulator.chamber_pa()});
    if (outlet) outlet->push_back({i * 0.001, regulator.outlet_pa()});
    sim.Wait(0.001);
  }
  return samples;
}

}  // namespace palpa::testing
