// The STM32F4 board shell: the firmware core on USART1 (DMA), two AD5724R DACs, ADC1 sensors,
// the independent watchdog, the valve enables and the E-stop input. Pin map: docs/stm32f4.md.
#include <new>

#include "board_shell.h"
#include "palpa/core/board.h"
#include "palpa/core/compiled_configs.h"
#include "palpa/hal/stm32f4/drivers.h"
#include "palpa/hal/stm32f4/registers.h"

#ifndef PALPA_BOARD_CONFIG
#define PALPA_BOARD_CONFIG "thesis-5finger"
#endif
#ifndef PALPA_BOARD_CONFIG_OBJECT
#define PALPA_BOARD_CONFIG_OBJECT k_thesis_5finger  // named, so only this one is linked
#endif

extern palpa::boards::ResetRecord g_reset_record;
extern "C" uint32_t _stack_guard;  // linker script: the lowest 32 bytes of the stack

namespace palpa::boards::stm32f4 {
namespace {

namespace hw = palpa::hal::stm32f4;

// Outputs on GPIOB: the valve drivers' pulsing enables and the pump; every one pulled low on
// the board, so a reset or a hung loop leaves them off.
constexpr uint8_t kSupplyEnablePin = 12, kDumpEnablePin = 13, kPumpEnablePin = 14, kEStopPin = 15;

// Built at startup in zeroed RAM (objects with vtables would otherwise copy their buffers from
// flash as .data).
alignas(hw::DmaUart) unsigned char g_uart_storage[sizeof(hw::DmaUart)];
hw::DmaUart& g_uart = *new (g_uart_storage) hw::DmaUart;
hw::CycleClock g_clock;
hw::Ad5724Dacs g_dac;
hw::ScanAdc g_adc;
hw::IndependentWatchdog g_watchdog;
hw::InternalFlash g_flash;
hw::GpioOutput g_supply(hw::kGpioB, kSupplyEnablePin), g_dump(hw::kGpioB, kDumpEnablePin),
    g_pump(hw::kGpioB, kPumpEnablePin);
hw::GpioInput g_estop(hw::kGpioB, kEStopPin, /*asserted_high=*/true);  // NC contact to ground
alignas(core::Board) unsigned char g_board_storage[sizeof(core::Board)];

void StackGuard() {
  // MPU region 0: the 32 bytes below the stack, no access, execute-never; the default map for
  // privileged code elsewhere. A stack overflow becomes a MemManage fault.
  *hw::kMpuRbar = (reinterpret_cast<uint32_t>(&_stack_guard) & ~31u) | (1u << 4) | 0u;
  *hw::kMpuRasr = (1u << 28) | (4u << 1) | 1u;
  *hw::kMpuCtrl = (1u << 2) | 1u;
  *hw::kScbShcsr |= (1u << 16) | (1u << 17) | (1u << 18);  // MemManage, BusFault, UsageFault
  asm volatile("dsb\n isb");
}

protocol::ResetCause CauseOfThisBoot() {
  const uint32_t flags = hw::TakeResetFlags();
  const protocol::ResetCause recorded = g_reset_record.Take();  // set by a fault handler
  if (recorded != protocol::ResetCause::kPowerOn) return recorded;
  if (flags & (hw::rcc::kCsrIwdg | hw::rcc::kCsrWwdg)) return protocol::ResetCause::kWatchdog;
  if (flags & hw::rcc::kCsrPor) return protocol::ResetCause::kPowerOn;  // POR also sets BORRSTF
  if (flags & hw::rcc::kCsrBor) return protocol::ResetCause::kBrownOut;
  if (flags & hw::rcc::kCsrSoftware) return protocol::ResetCause::kSoftware;
  if (flags & hw::rcc::kCsrPin) return protocol::ResetCause::kPin;
  return protocol::ResetCause::kUnknown;
}

uint32_t UniqueId() {  // RM0090 §39.1: 96-bit unique device ID
  const auto* uid = reinterpret_cast<const volatile uint32_t*>(0x1FFF7A10u);
  return uid[0] ^ uid[1] ^ uid[2];
}

}  // namespace

void ForceOutputsSafe() {
  hw::Ad5724Dacs::ClearAllOutputs();
  hw::kRcc->AHB1ENR |= hw::rcc::kAhb1GpioB;
  hw::kGpioB->BSRR = (1u << (kSupplyEnablePin + 16u)) | (1u << (kDumpEnablePin + 16u)) |
                     (1u << (kPumpEnablePin + 16u));
}

}  // namespace palpa::boards::stm32f4

int main() {
  using namespace palpa::boards::stm32f4;
  namespace hw = palpa::hal::stm32f4;
  const palpa::protocol::ResetCause cause = CauseOfThisBoot();
  hw::EnsureBrownOutLevel();
  hw::ConfigureClocks();
  StackGuard();
  g_clock.Init();
  g_supply.Init(false);
  g_dump.Init(false);
  g_pump.Init(false);
  g_estop.Init();
  g_dac.Init();
  g_adc.Init();
  g_uart.Init();

  const palpa::core::BoardConfig* config = &palpa::core::PALPA_BOARD_CONFIG_OBJECT;
  palpa::core::BoardIdentity id;
  id.kind = palpa::protocol::BoardKind::kStm32f4;
  id.board_id = UniqueId();
  id.reset_cause = cause;
  id.boot_count = g_reset_record.boot_count;
  id.boot_nonce = id.board_id ^ (g_reset_record.boot_count * 2654435761u) ^ *hw::kDwtCyccnt;
  id.rx_buffer_bytes = hw::DmaUart::kRxSize;
  auto* board = new (g_board_storage)
      palpa::core::Board(*config,
                         palpa::core::BoardIo{g_clock, g_dac, &g_adc, g_supply, g_dump, g_pump,
                                              &g_estop, g_uart, &g_flash, 0},
                         id);
  board->Start();
  g_watchdog.Start(30);
  for (;;) {
    if (board->Step()) g_watchdog.Kick();  // only after a tick wrote its outputs
    g_uart.PumpTx();
  }
}
