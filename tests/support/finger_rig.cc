// The simulated finger rig: protocol frames into an in-process board, rig model for readings.
#include "finger_rig.h"

#include <algorithm>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/crc32.h"

namespace palpa::testing {
namespace pp = protocol;

FingerRig::FingerRig(const FingerRigOptions& options) : options_(options), rig_(options.seed * 31u + 7u) {
  sim::SimBoardOptions o;
  o.config = "thesis-5finger";
  o.plant.level = 3;
  o.plant.unit = options.unit;
  o.plant.seed = options.seed;
  o.plant.effects = options.effects;
  std::string error;
  sim_ = sim::SimBoard::Create(o, link_, &error);
  const pp::ConfigureFinger& f = sim_->board().config().fingers[options.finger];
  jamming_ = f.kind == pp::FingerKind::kJamming;
  driven_line_ = jamming_ ? f.line_b : f.line_a;
  const pp::ConfigureLine& line = sim_->board().config().lines[driven_line_];
  drive_max_ = jamming_ ? -line.limit_min_pa : line.limit_max_pa;
  Send(pp::Hello{1, 0}, false);
  Run(5);
  // Every other finger stays vented in raw mode: only this one moves.
  for (uint8_t other = 0; other < sim_->board().config().finger_count; ++other) {
    if (other != options.finger) Send(pp::SetFingerMode{other, pp::FingerMode::kRaw}, true);
  }
  Send(pp::SetFingerMode{options.finger, pp::FingerMode::kRaw}, true);
  Run(5);
  if (!jamming_) rig_.Zero(0);
}

template <class M>
void FingerRig::Send(const M& m, bool reliable) {
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, reliable ? seq_++ : 0, reliable ? pp::flags::kReliable : 0, frame, sizeof(frame));
  link_.Inject(frame, n.value);
  sim_->Advance(1);  // dispatched between ticks
}

void FingerRig::Run(int ms) {
  for (int k = 0; k < ms; ++k) {
    if (k % 20 == 0) Send(pp::Heartbeat{++generation_}, false);
    sim_->Advance(1000 - (sim_->now_us() % 1000));
    link_.tx.clear();
  }
}

double FingerRig::MeasuredDrive() const {
  const pp::ConfigureLine& c = sim_->board().config().lines[driven_line_];
  const double counts = sim_->plant().SensorCounts(driven_line_);
  const double pa = c.sensor_min_pa + (counts - c.sensor_counts_min) * (c.sensor_max_pa - c.sensor_min_pa) /
                                          static_cast<double>(c.sensor_counts_max - c.sensor_counts_min);
  return jamming_ ? -pa : pa;
}

double FingerRig::RigOutput() {
  if (jamming_) return 1000.0 * rig_.Stiffness(*sim_->plant().jamming(options_.finger));
  return 1000.0 * rig_.Deformation(sim_->plant().Truth().fingers[options_.finger].deformation_mm);
}

double FingerRig::TruthOutput() const {
  const sim::FingerTruth t = sim_->plant().Truth().fingers[options_.finger];
  return 1000.0 * (jamming_ ? t.stiffness_n_per_mm : t.deformation_mm);
}

bool FingerRig::Saturated() const {
  return (sim_->board().line_output(driven_line_).status & pp::line_status::kSaturated) != 0;
}

std::vector<calibration::SweepSample> FingerRig::Sweep(const std::vector<double>& drives, int dwell_ms) {
  if (target_mode_) {
    Send(pp::SetFingerMode{options_.finger, pp::FingerMode::kRaw}, true);
    target_mode_ = false;
  }
  const pp::ConfigureFinger& f = sim_->board().config().fingers[options_.finger];
  std::vector<calibration::SweepSample> out;
  for (double drive : drives) {
    pp::SetLineSetpoints sp{};
    sp.generation = ++generation_;
    if (jamming_) {
      sp.entries[sp.entry_count++] = {f.line_a, f.bias_pa};
      sp.entries[sp.entry_count++] = {f.line_b, static_cast<int32_t>(-drive)};
    } else {
      sp.entries[sp.entry_count++] = {f.line_a, static_cast<int32_t>(drive)};
    }
    Send(sp, false);
    Run(dwell_ms);
    out.push_back({MeasuredDrive(), RigOutput()});
  }
  return out;
}

pp::Status FingerRig::Configure(const std::vector<pp::InversePoint>& inverse, pp::CompensatorKind kind,
                                const std::vector<float>& params, std::string* reason) {
  pp::ConfigureFinger f = sim_->board().config().fingers[options_.finger];
  f.inverse_count = static_cast<uint8_t>(inverse.size());
  std::copy(inverse.begin(), inverse.end(), f.inverse.begin());
  f.compensator = kind;
  f.param_count = static_cast<uint8_t>(params.size());
  std::copy(params.begin(), params.end(), f.params.begin());
  // Straight to the board's validation and apply path (what a staged upload ends in).
  core::ConfigError error;
  const pp::Status s = core::ValidateFinger(f, sim_->board().config(), &error);
  if (s != pp::Status::kOk) {
    if (reason != nullptr) *reason = error.reason;
    return s;
  }
  uint8_t records[512];
  const auto size = pp::EncodeBody(f, records + 3, sizeof(records) - 3);
  if (size.ok() && size.value <= pp::kMaxBodySize) {
    Send(f, true);
  } else {  // over one packet: a staged upload of one record, as the host library sends it
    records[0] = static_cast<uint8_t>(size.value);
    records[1] = static_cast<uint8_t>(size.value >> 8);
    records[2] = static_cast<uint8_t>(pp::MessageType::kConfigureFinger);
    const size_t total = size.value + 3;
    Send(pp::StagedBegin{static_cast<uint16_t>(total)}, true);
    for (size_t at = 0; at < total; at += pp::kMaxStagedChunk) {
      pp::StagedPart part{};
      part.offset = static_cast<uint16_t>(at);
      part.data_size = static_cast<uint8_t>(std::min<size_t>(pp::kMaxStagedChunk, total - at));
      std::copy(records + at, records + at + part.data_size, part.data.begin());
      Send(part, true);
    }
    Send(pp::StagedCommit{static_cast<uint16_t>(total), pp::Crc32(records, total)}, true);
  }
  Run(5);
  target_mode_ = false;
  return sim_->board().config().fingers[options_.finger].compensator == kind ? pp::Status::kOk : pp::Status::kUnavailable;
}

void FingerRig::Follow(double target, int ms, const std::function<void(double)>& each_ms) {
  if (!target_mode_) {
    Send(pp::SetFingerMode{options_.finger, pp::FingerMode::kTarget}, true);
    target_mode_ = true;
  }
  pp::SetFingerTargets t{};
  t.generation = ++generation_;
  t.entries[t.entry_count++] = {options_.finger,
                                jamming_ ? pp::OutputUnit::kStiffnessMilliNewtonPerMm : pp::OutputUnit::kDeformationMicrometre,
                                static_cast<int32_t>(std::lround(target))};
  Send(t, false);
  for (int k = 0; k < ms; ++k) {
    Run(1);
    if (each_ms) each_ms(TruthOutput());
  }
}

}  // namespace palpa::testing
