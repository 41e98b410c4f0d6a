// Control-tick workload for instruction counting: thesis-5finger (or another configuration)
// with every finger following a target, sensors reading the regulator model, telemetry on.
//   palpa_tick_bench CONFIG TICKS
#include <cstdio>
#include <cstdlib>

#include "palpa/core/board.h"
#include "palpa/core/board_configs.h"
#include "palpa/hal/fake/fakes.h"
#include "palpa/protocol/codec.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;
namespace fake = palpa::hal::fake;

namespace {

template <class M>
void Send(fake::FakeByteLink& link, const M& m, uint8_t seq, uint8_t flags) {
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(m, seq, flags, frame, sizeof(frame));
  link.Inject(frame, n.value);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: palpa_tick_bench CONFIG TICKS\n");
    return 2;
  }
  const pc::BoardConfig* config = pc::FindBoardConfig(argv[1]);
  if (config == nullptr) {
    std::fprintf(stderr, "no configuration '%s'\n", argv[1]);
    return 2;
  }
  const long ticks = std::strtol(argv[2], nullptr, 10);
  fake::FakeClock clock;
  fake::FakeAnalogOutput dac;
  fake::FakeAnalogInput adc;
  fake::FakeDigitalOutput supply, dump, pump;
  fake::FakeByteLink link;
  pc::Board board(*config,
                  pc::BoardIo{clock, dac, &adc, supply, dump, pump, nullptr, link, nullptr, 0},
                  pc::BoardIdentity{});
  auto follow_model = [&] {
    for (uint8_t i = 0; i < config->line_count; ++i) {
      const pp::ConfigureLine& c = config->lines[i];
      const float fraction =
          (board.line_state(i).reference_pa - static_cast<float>(c.sensor_min_pa)) /
          static_cast<float>(c.sensor_max_pa - c.sensor_min_pa);
      adc.counts[i] = static_cast<uint32_t>(
          static_cast<float>(c.sensor_counts_min) +
          fraction * static_cast<float>(c.sensor_counts_max - c.sensor_counts_min));
    }
  };
  board.Start();
  follow_model();
  Send(link, pp::Hello{1, 0}, 0, 0);
  pp::SetFingerTargets targets{};
  targets.session = 1;  // the Hello's nonce
  targets.generation = 1;
  for (uint8_t f = 0; f < config->finger_count; ++f) {
    const bool jamming = config->fingers[f].kind == pp::FingerKind::kJamming;
    targets.entries[targets.entry_count++] =
        pp::FingerTarget{f, pc::UnitOf(config->fingers[f].kind), jamming ? 1000 : 1500};
  }
  Send(link, targets, 0, 0);
  uint32_t generation = 1;
  for (long t = 0; t < ticks; ++t) {
    clock.Advance(pc::Board::kTickUs);
    if (t % 20 == 0) Send(link, pp::Heartbeat{1, ++generation}, 0, 0);
    board.Step();
    link.tx.clear();
    follow_model();
  }
  if (board.safe() || board.latched_faults() != 0) {
    std::fprintf(stderr, "the board went safe (faults 0x%x): the workload is wrong\n",
                 board.latched_faults());
    return 1;
  }
  return 0;
}
