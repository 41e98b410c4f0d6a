// The simulated finger rig: protocol frames into an in-process board, rig model for readings.
#include "finger_rig.h"

#include <algorithm>
#include <cmath>

namespace palpa::testing {
namespace pp = protocol;

FingerRig::FingerRig(const FingerRigOptions& options)
    : options_(options),
      board_(PlantBoardOptions("thesis-5finger", options.unit, options.seed, options.effects)),
      rig_(options.seed * 31u + 7u) {
  const pp::ConfigureFinger& f = board_.config().fingers[options.finger];
  jamming_ = f.kind == pp::FingerKind::kJamming;
  driven_line_ = jamming_ ? f.line_b : f.line_a;
  const pp::ConfigureLine& line = board_.config().lines[driven_line_];
  drive_max_ = jamming_ ? -line.limit_min_pa : line.limit_max_pa;
  // Every other finger stays vented in raw mode: only this one moves.
  for (uint8_t other = 0; other < board_.config().finger_count; ++other) {
    if (other != options.finger) board_.Send(pp::SetFingerMode{other, pp::FingerMode::kRaw});
  }
  board_.Send(pp::SetFingerMode{options.finger, pp::FingerMode::kRaw});
  board_.Run(5);
  if (!jamming_) rig_.Zero(0);
}

double FingerRig::MeasuredDrive() const {
  const double pa = board_.SensorPa(driven_line_);
  return jamming_ ? -pa : pa;
}

double FingerRig::RigOutput() {
  if (jamming_) return 1000.0 * rig_.Stiffness(*board_.sim().plant().jamming(options_.finger));
  // As the calibration reads a sweep point: the mean of its touches (the rig's repeatability).
  const int touches = std::max(1, calibration::ContactOptions{}.touches);
  double sum = 0;
  for (int t = 0; t < touches; ++t)
    sum += rig_.Deformation(board_.sim().plant().Truth().fingers[options_.finger].deformation_mm);
  return 1000.0 * sum / touches;
}

double FingerRig::TruthOutput() const {
  const sim::FingerTruth t = board_.sim().plant().Truth().fingers[options_.finger];
  return 1000.0 * (jamming_ ? t.stiffness_n_per_mm : t.deformation_mm);
}

bool FingerRig::Saturated() const {
  return (board_.sim().board().line_output(driven_line_).status & pp::line_status::kSaturated) != 0;
}

std::vector<calibration::SweepSample> FingerRig::Sweep(const std::vector<double>& drives,
                                                       int dwell_ms) {
  if (target_mode_) {
    board_.Send(pp::SetFingerMode{options_.finger, pp::FingerMode::kRaw});
    target_mode_ = false;
  }
  const pp::ConfigureFinger& f = board_.sim().board().config().fingers[options_.finger];
  std::vector<calibration::SweepSample> out;
  for (double drive : drives) {
    pp::SetLineSetpoints sp{};
    sp.session = InProcessBoard::kSession;
    sp.generation = board_.next_generation();
    if (jamming_) {
      sp.entries[sp.entry_count++] = {f.line_a, f.bias_pa};
      sp.entries[sp.entry_count++] = {f.line_b, static_cast<int32_t>(-drive)};
    } else {
      sp.entries[sp.entry_count++] = {f.line_a, static_cast<int32_t>(drive)};
    }
    board_.Send(sp);
    board_.Run(dwell_ms);
    out.push_back({MeasuredDrive(), RigOutput()});
  }
  return out;
}

palpa::host::Outcome FingerRig::Configure(const std::vector<pp::InversePoint>& inverse,
                                          pp::CompensatorKind kind,
                                          const std::vector<float>& params) {
  pp::ConfigureFinger f = board_.sim().board().config().fingers[options_.finger];
  f.inverse_count = static_cast<uint8_t>(inverse.size());
  std::copy(inverse.begin(), inverse.end(), f.inverse.begin());
  f.compensator = kind;
  f.param_count = static_cast<uint8_t>(params.size());
  std::copy(params.begin(), params.end(), f.params.begin());
  // Straight to the board's validation and apply path (what a staged upload ends in).
  core::ConfigError error;
  const pp::Status s = core::ValidateFinger(f, board_.sim().board().config(), &error);
  if (s != pp::Status::kOk) return palpa::host::Outcome::Fail(s, error.reason);
  board_.SendConfig(f);
  board_.Run(5);
  target_mode_ = false;
  if (board_.sim().board().config().fingers[options_.finger].compensator != kind) {
    return palpa::host::Outcome::Fail(pp::Status::kUnavailable,
                                      "the board did not take the compensator");
  }
  return {};
}

void FingerRig::Follow(double target, int ms, const std::function<void(double)>& each_ms) {
  if (!target_mode_) {
    board_.Send(pp::SetFingerMode{options_.finger, pp::FingerMode::kTarget});
    target_mode_ = true;
  }
  pp::SetFingerTargets t{};
  t.session = InProcessBoard::kSession;
  t.generation = board_.next_generation();
  t.entries[t.entry_count++] = {options_.finger,
                                jamming_ ? pp::OutputUnit::kStiffnessMilliNewtonPerMm
                                         : pp::OutputUnit::kDeformationMicrometre,
                                static_cast<int32_t>(std::lround(target))};
  board_.Send(t);
  for (int k = 0; k < ms; ++k) {
    board_.Run(1);
    if (each_ms) each_ms(TruthOutput());
  }
}

}  // namespace palpa::testing
