// Links firmware/core (with protocol/) into a program with no C or C++ runtime: any heap use,
// exception, RTTI or static-init guard leaves an undefined symbol and fails the build.
#include "palpa/core/board.h"
#include "palpa/core/board_configs.h"

#include "bare_runtime.h"

namespace pc = palpa::core;
namespace hal = palpa::hal;

namespace {

struct Clock final : hal::Clock {
  uint64_t now = 0;
  uint64_t DoNowMicros() override { return now += 250; }
};
struct Dac final : hal::AnalogOutput {
  uint32_t last = 0;
  palpa::protocol::Status DoWrite(uint8_t, uint32_t counts) override {
    last = counts;
    return palpa::protocol::Status::kOk;
  }
  hal::AnalogOutputSpec DoSpec(uint8_t) const override { return {}; }
};
struct Pin final : hal::DigitalOutput {
  palpa::protocol::Status DoSet(bool) override { return palpa::protocol::Status::kOk; }
};
struct Link final : hal::ByteLink {
  size_t DoRead(uint8_t*, size_t) override { return 0; }
  size_t DoWrite(const uint8_t*, size_t size) override { return size; }
  size_t DoWriteSpace() const override { return 1024; }
};

Clock g_clock;
Dac g_dac;
Pin g_supply, g_dump, g_pump;
Link g_link;

}  // namespace

extern "C" int palpa_check_main() {
  const pc::BoardConfig* config = pc::FindBoardConfig("thesis-5finger");
  if (config == nullptr) return 1;
  static pc::Board board(
      *config,
      pc::BoardIo{g_clock, g_dac, nullptr, g_supply, g_dump, g_pump, nullptr, g_link, nullptr, 0},
      pc::BoardIdentity{});
  board.Start();
  for (int i = 0; i < 100; ++i) board.Step();
  return board.safe() ? 0 : 2;
}
