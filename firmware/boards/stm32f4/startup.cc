// Cortex-M4 startup for the STM32F4 board: vector table, reset (DAC cleared first, FPU, .data,
// .bss, constructors), and the fault handlers that force the outputs safe and reset.
#include <cstdint>

#include "../common/cortex_m_runtime.h"
#include "board_shell.h"
#include "palpa/hal/stm32f4/registers.h"

namespace stm32f4 = palpa::hal::stm32f4;

__attribute__((section(".noinit"))) palpa::boards::ResetRecord g_reset_record;

namespace {

[[noreturn]] void SafeAndReset(palpa::protocol::ResetCause cause) {
  palpa::boards::stm32f4::ForceOutputsSafe();  // Critical for safety: before anything else
  g_reset_record.Set(cause);
  // The record must reach RAM before the reset: the clobber keeps the compiler from dropping the
  // stores (nothing it can see reads them again), the DSB drains the write buffer (as CMSIS does).
  asm volatile("dsb" ::: "memory");
  *stm32f4::kScbAircr = (0x5FAu << 16) | (1u << 2);  // SYSRESETREQ
  for (;;) {
  }
}

}  // namespace

extern "C" {

void Reset_Handler() {
  // The DAC's CLR line has a pull-down, so the outputs sit at 0 V through reset; drive it low
  // explicitly before anything else runs, then bring the rest of the chip up.
  palpa::boards::stm32f4::ForceOutputsSafe();
  palpa::boards::StartRuntimeAndMain();
}

void NMI_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }  // clock security
void HardFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void MemManage_Handler() {
  SafeAndReset(palpa::protocol::ResetCause::kFaultHandler);
}  // stack guard
void BusFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void UsageFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void Default_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }

// No interrupt is enabled (the link and the ADC run on DMA, the clock on the cycle counter), so
// every IRQ slot goes to the fault path: an unexpected interrupt is a fault.
#define PALPA_DEFAULT_8                                                                \
  Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, \
      Default_Handler, Default_Handler, Default_Handler
__attribute__((section(".isr_vector"), used)) void (*const g_vectors[16 + 82])() = {
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
    Default_Handler,  // SysTick (unused)
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    PALPA_DEFAULT_8,
    Default_Handler,
    Default_Handler,
};
#undef PALPA_DEFAULT_8

}  // extern "C"
