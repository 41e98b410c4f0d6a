// In-process board plumbing: heartbeats, staged uploads, sensor readings.
#include "in_process_board.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "palpa/protocol/crc32.h"

namespace palpa::testing {
namespace pp = protocol;

sim::SimBoardOptions PlantBoardOptions(const std::string& config, uint32_t unit, uint32_t seed,
                                       sim::Effects effects) {
  sim::SimBoardOptions o;
  o.config = config;
  o.plant.level = 3;
  o.plant.unit = unit;
  o.plant.seed = seed;
  o.plant.effects = effects;
  return o;
}

InProcessBoard::InProcessBoard(const sim::SimBoardOptions& options) {
  auto created = sim::SimBoard::Create(options, link_);
  if (!created.ok()) {  // a test's own options: say which, rather than run on nothing
    std::fprintf(stderr, "InProcessBoard: %s\n", created.message.c_str());
    std::abort();
  }
  sim_ = std::move(created.value);
  Send(pp::Hello{kSession, 0}, false);
  Run(5);
}

void InProcessBoard::Run(int ms) {
  for (int k = 0; k < ms; ++k) {
    if (since_heartbeat_ms_ <= 0) {
      Send(pp::Heartbeat{kSession, next_generation()}, false);
      since_heartbeat_ms_ = 20;
    }
    --since_heartbeat_ms_;
    sim_->Advance(1000 - (sim_->now_us() % 1000));
    link_.tx.clear();
  }
}

template <class M>
void InProcessBoard::SendConfig(const M& m) {
  uint8_t records[600];
  const auto size = pp::EncodeBody(m, records + 3, sizeof(records) - 3);
  if (size.ok() && size.value <= pp::kMaxBodySize) {
    Send(m, true);
    return;
  }
  // Over one packet: a staged upload of one record, as the host library sends it.
  records[0] = static_cast<uint8_t>(size.value);
  records[1] = static_cast<uint8_t>(size.value >> 8);
  records[2] = static_cast<uint8_t>(M::kInfo.type);
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

template void InProcessBoard::SendConfig(const pp::ConfigureFinger&);
template void InProcessBoard::SendConfig(const pp::ConfigureLine&);

double InProcessBoard::SensorPa(uint8_t line) const {
  const pp::ConfigureLine& c = config().lines[line];
  const double counts = sim_->plant().SensorCounts(line);
  return c.sensor_min_pa + (counts - c.sensor_counts_min) * (c.sensor_max_pa - c.sensor_min_pa) /
                               static_cast<double>(c.sensor_counts_max - c.sensor_counts_min);
}

}  // namespace palpa::testing
