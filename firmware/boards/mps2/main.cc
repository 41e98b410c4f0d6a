// The MPS2 AN386 board shell: the firmware core on the CMSDK UART, SysTick and watchdog, with the
// level-1 plant behind the analogue interfaces. Variants (compile definitions):
//   PALPA_SELFTEST       boot, run 2 s of ticks, report identity over semihosting and exit
//   PALPA_HANG_AFTER_MS  hang inside a tick after that long (the watchdog test); with SELFTEST, a
//                        boot after a watchdog reset reports the cause and exits
//   PALPA_BENCH          an in-image host: a session, every finger following a target, heartbeats;
//                        runs 3 000 ticks and exits (instruction counting under QEMU); with
//                        PALPA_BENCH_PI16 a PI(16) compensator on every finger, PALPA_BENCH_SHAPED
//                        shaped steps on every line, PALPA_BENCH_CORRECTED a regulator correction
//                        on every line
#include <cstdio>
#include <new>

#include "bench_host.h"
#include "board_shell.h"
#include "palpa/core/board.h"
#include "palpa/core/compiled_configs.h"
#include "palpa/core/flash_layout.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/mps2/code_flash.h"
#include "palpa/hal/mps2/drivers.h"
#include "palpa/hal/mps2/registers.h"
#include "palpa/protocol/catalog.h"
#include "plant_io.h"
#include "semihosting.h"

#ifndef PALPA_BOARD_CONFIG
#define PALPA_BOARD_CONFIG "thesis-5finger"
#endif
#ifndef PALPA_BOARD_CONFIG_OBJECT
#define PALPA_BOARD_CONFIG_OBJECT k_thesis_5finger  // named, so only this one is linked
#endif

extern palpa::boards::mps2::ResetRecord g_reset_record;
extern "C" uint32_t _stack_guard;  // linker script: the lowest 32 bytes of the stack

namespace palpa::boards::mps2 {
namespace {

namespace hal_mps2 = palpa::hal::mps2;

class NullPin final : public hal::DigitalOutput {
  hal::Status DoSet(bool) override { return hal::Status::kOk; }
};

// Valve drivers on the MPS2 are modelled: the plant vents unless both enables keep toggling.
class PulsePin final : public hal::DigitalOutput {
 public:
  bool toggled = false;

 private:
  hal::Status DoSet(bool level) override {
    toggled |= level != level_;
    level_ = level;
    return hal::Status::kOk;
  }
  bool level_ = false;
};

#ifdef PALPA_NO_PLANT
// The control image alone, for the flash and RAM budget: analogue I/O that goes nowhere.
class NullIo final : public hal::AnalogOutput, public hal::AnalogInput {
 public:
  void Init(const core::BoardConfig&) {}
  void Step(bool, uint32_t) {}

 private:
  protocol::Status DoWrite(uint8_t, uint32_t) override { return protocol::Status::kOk; }
  hal::AnalogOutputSpec DoSpec(uint8_t) const override { return {}; }
  protocol::Result<uint32_t> DoRead(uint8_t) override { return 8192u; }
  uint8_t DoBits() const override { return 14; }
};
using Io = NullIo;
#else
using Io = PlantIo;
#endif

// Built at startup in zeroed RAM: a static Uart (it has a vtable) would land in .data and copy
// its 3 KB of rings from flash.
alignas(hal_mps2::Uart) uint8_t g_uart_storage[sizeof(hal_mps2::Uart)];
hal_mps2::Uart& g_uart = *new (g_uart_storage) hal_mps2::Uart;
hal_mps2::SysTickClock g_clock;
hal_mps2::CmsdkWatchdogDriver g_watchdog;
Io g_plant;
PulsePin g_supply, g_dump;
NullPin g_pump;
// The lines' dump valve drivers, a port of one bit per line (set: released, the valve open).
class VentPort final : public hal::DigitalPort {
 public:
  uint32_t bits = ~0u;

 private:
  uint8_t DoWrite(uint32_t value) override {
    bits = value;
    return kAllWritten;
  }
};
VentPort g_vents;
alignas(core::Board) unsigned char g_board_storage[sizeof(core::Board)];
core::Board* g_board = nullptr;

void StackGuard() {
  // MPU region 0: the 32 bytes below the stack, no access (AP=0), enabled; background map for
  // privileged code (PRIVDEFENA). A stack overflow becomes a MemManage fault.
  *hal_mps2::kMpuRbar = (reinterpret_cast<uint32_t>(&_stack_guard) & ~31u) | (1u << 4) | 0u;
  *hal_mps2::kMpuRasr = (1u << 28) | (4u << 1) | 1u;  // XN, size 2^(4+1) = 32 bytes, enable
  *hal_mps2::kMpuCtrl = (1u << 2) | 1u;
  *hal_mps2::kScbShcsr |= 1u << 16;  // MemManage fault enabled
  asm volatile("dsb\n isb");
}

[[maybe_unused]] void Print(const char* text) {
#ifdef PALPA_SELFTEST
  SemihostPrint(text);
#else
  (void)text;
#endif
}

/// Who this board is, for Hello: an MPS2 AN386 with a simulated plant, its boot count and
/// nonce, and why it last reset.
core::BoardIdentity Identity(protocol::ResetCause cause) {
  core::BoardIdentity id;
  id.kind = protocol::BoardKind::kMps2An386;
  id.board_id = 386;
  id.plant_simulated = true;
  id.reset_cause = cause;
  id.boot_count = g_reset_record.boot_count;
  id.boot_nonce = 0x4D505332u ^ (g_reset_record.boot_count * 2654435761u);
  id.rx_buffer_bytes = hal_mps2::Uart::kRxSize;
  return id;
}

/// The update engine of an image started by the bootloader from a slot (VTOR says which):
/// updates go to the other one. None for an image linked to run alone.
core::UpdateEngine* SlotUpdates(core::BoardIdentity& id) {
#ifdef PALPA_SLOT_IMAGE
  const core::FlashLayout& layout = core::kDefaultLayout;
  static hal_mps2::CodeFlash flash(layout.xip_base, layout.total, layout.sector_size);
  id.active_slot = *hal_mps2::kScbVtor >= layout.slot_offset[1] ? 1 : 0;
  static core::UpdateEngine engine(&flash, layout, id.kind, id.active_slot, &g_watchdog);
  id.rollback_counter = engine.rollback_floor();
  return &engine;
#else
  (void)id;
  return nullptr;
#endif
}

void StartBoard(const core::BoardConfig& config, const core::BoardIdentity& id,
                core::UpdateEngine* update) {
  g_board = new (g_board_storage)
      core::Board(config,
                  core::BoardIo{g_clock, g_plant, &g_plant, g_supply, g_dump, g_pump, nullptr,
                                g_uart, nullptr, 0, update, &g_vents},
                  id);
  g_board->Start();
}

/// The plant follows the board's clock, 1 ms steps. It stands in for the world, which moves on
/// while a long command (a hash of both slots: about 300 ms of this core) holds the loop, so it
/// catches up before the next tick reads it. Those steps are the world's time, not the
/// firmware's: each kicks the watchdog, which still measures every stretch of the firmware's own
/// work (a hung tick never gets here). Without it, catching up after 180 ms took longer than the
/// watchdog's 30 ms and reset a board that had done nothing wrong.
void CatchUpPlant(uint64_t now_us, uint64_t& plant_ms) {
  while (plant_ms * 1000 < now_us) {
    const bool held = g_supply.toggled && g_dump.toggled;
    g_plant.Step(!held || g_board->safe(), g_vents.bits);
    ++plant_ms;
    g_watchdog.Kick();
  }
}

/// UpdateReboot: its Ack out first, then the bootloader.
void RebootIfAsked() {
  if (!g_board->reboot_requested()) return;
  g_uart.DrainTx();  // within the watchdog's period: it was kicked after the last tick
  g_reset_record.Set(protocol::ResetCause::kUpdate);
  hal_mps2::SystemReset();
}

#ifdef PALPA_SELFTEST
/// A boot after a watchdog reset: outputs safe and the fault latched, or the test fails.
void ReportWatchdogBoot(protocol::ResetCause cause) {
  if (cause != protocol::ResetCause::kWatchdog) return;
  Print("palpa mps2-an386: booted after a watchdog reset; outputs safe, fault latched\n");
  SemihostExit(g_board->safe() && (g_board->latched_faults() & 0x10u) ? 42 : 1);
}

/// After 2 s of ticks: identity and tick counts over semihosting, and exit.
void ReportAfterTwoSeconds(uint64_t now_us) {
  if (now_us <= 2000000) return;
  char text[160];
  std::snprintf(text, sizeof(text),
                "palpa mps2-an386 firmware 0.1.0, catalog 0x%08lx, %s, %lu ticks, %lu "
                "overruns, safe=%d\n",
                static_cast<unsigned long>(protocol::kCatalogHash), PALPA_BOARD_CONFIG,
                static_cast<unsigned long>(g_board->tick_stats().ticks),
                static_cast<unsigned long>(g_board->tick_stats().overruns),
                g_board->safe() ? 1 : 0);
  Print(text);
  SemihostExit(g_board->tick_stats().ticks >= 1900 && g_board->safe() ? 0 : 1);
}
#endif

#ifdef PALPA_BENCH
/// What the benchmark images' in-image host drives (bench_host.h).
struct BenchShell {
  static hal_mps2::Uart& Uart() { return g_uart; }
  static const core::Board& Board() { return *g_board; }
  static hal_mps2::SysTickClock& Clock() { return g_clock; }
};
#endif

}  // namespace

void WriteSafeCodes() {
  // The plant stands in for a DAC: every command to 0 Pa (every compiled-in safe value).
  for (uint8_t i = 0; i < protocol::kMaxLines; ++i)
    static_cast<hal::AnalogOutput&>(g_plant).Write(i, 0);
}

void OnSysTick() { g_clock.OnTick(); }
void OnUartRx() { g_uart.OnRxInterrupt(); }

}  // namespace palpa::boards::mps2

int main() {
  using namespace palpa::boards::mps2;
  const palpa::protocol::ResetCause cause = g_reset_record.Take();
  const palpa::core::BoardConfig* config = &palpa::core::PALPA_BOARD_CONFIG_OBJECT;
#ifdef PALPA_BENCH_PI16
  config = WithPi16OnEveryFinger(*config);
#endif
  g_plant.Init(*config);
  StackGuard();
  g_uart.Init();
  g_clock.Init();
  palpa::core::BoardIdentity id = Identity(cause);
  palpa::core::UpdateEngine* update = SlotUpdates(id);
  StartBoard(*config, id, update);
#ifdef PALPA_SELFTEST
  ReportWatchdogBoot(cause);
#endif
  g_watchdog.Start(30);
  uint64_t plant_ms = 0;
#ifdef PALPA_BENCH
  BenchHost<BenchShell> bench(*config);
#endif
  for (;;) {
    const uint64_t now = g_clock.NowMicros();
#ifdef PALPA_BENCH
    bench.Heartbeat(now);
#endif
    if (g_board->Step()) {
      g_watchdog.Kick();  // only after a tick wrote its outputs
#ifdef PALPA_BENCH
      bench.Ticked();
#endif
#ifdef PALPA_HANG_AFTER_MS
      if (now > PALPA_HANG_AFTER_MS * 1000ull) {
        for (;;) {  // a hung tick: the watchdog must take over
        }
      }
#endif
    }
    CatchUpPlant(now, plant_ms);
    g_uart.PumpTx();
    RebootIfAsked();
#ifdef PALPA_SELFTEST
    ReportAfterTwoSeconds(now);
#endif
  }
}
