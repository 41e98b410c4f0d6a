// Cortex-M4 startup for the MPS2 AN386: vector table, reset (FPU, .data, .bss, constructors),
// and the fault and watchdog handlers that write safe codes before anything else and reset.
#include <cstdint>

#include "../common/cortex_m_runtime.h"
#include "board_shell.h"
#include "palpa/hal/mps2/registers.h"

namespace mps2 = palpa::hal::mps2;
using palpa::boards::mps2::ResetRecord;

// The reset cause survives the reset in RAM that startup does not touch.
__attribute__((section(".noinit"))) ResetRecord g_reset_record;

namespace {

[[noreturn]] void SafeAndReset(palpa::protocol::ResetCause cause) {
  palpa::boards::mps2::WriteSafeCodes();  // Critical for safety: before anything else
  g_reset_record.Set(cause);
  mps2::SystemReset();
}

}  // namespace

extern "C" {

void Reset_Handler() {
  // A real board clears its DAC here, through the DAC's CLR pin, before anything else. On the
  // MPS2 the "DAC" is the plant model in RAM, which starts at 0 Pa with the zeroed .bss below.
  palpa::boards::StartRuntimeAndMain();
}

// The watchdog's first expiry: the loop stopped kicking it (a tick hung). Safe first, then reset.
void NMI_Handler() { SafeAndReset(palpa::protocol::ResetCause::kWatchdog); }
void HardFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void MemManage_Handler() {
  SafeAndReset(palpa::protocol::ResetCause::kFaultHandler);
}  // stack guard
void BusFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void UsageFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void Default_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void SysTick_Handler() { palpa::boards::mps2::OnSysTick(); }
void Uart0Rx_Handler() { palpa::boards::mps2::OnUartRx(); }

__attribute__((section(".isr_vector"), used)) void (*const g_vectors[16 + 16])() = {
    reinterpret_cast<void (*)()>(&_estack),
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    MemManage_Handler,
    BusFault_Handler,
    UsageFault_Handler,
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // debug monitor
    nullptr,
    Default_Handler,  // PendSV
    SysTick_Handler,
    Uart0Rx_Handler,  // IRQ 0: UART0 receive
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
    Default_Handler,
};

}  // extern "C"
