// Cortex-M4 startup for the MPS2 AN386: vector table, reset (FPU, .data, .bss, constructors),
// and the fault and watchdog handlers that write safe codes before anything else and reset.
#include <cstdint>

#include "board_shell.h"
#include "palpa/hal/mps2/registers.h"

extern "C" {
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();
void Reset_Handler();
void NMI_Handler();
void HardFault_Handler();
void MemManage_Handler();
void BusFault_Handler();
void UsageFault_Handler();
void SysTick_Handler();
void Uart0Rx_Handler();
void Default_Handler();
}

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
  *mps2::kScbCpacr |= 0xFu << 20;  // CP10 and CP11: the FPU, before any float instruction
  asm volatile("dsb\n isb");
  uint32_t* src = &_sidata;
  for (uint32_t* dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  for (auto* init = __init_array_start; init < __init_array_end; ++init) (*init)();
  main();
  for (;;) {
  }
}

// The watchdog's first expiry: the loop stopped kicking it (a tick hung). Safe first, then reset.
void NMI_Handler() { SafeAndReset(palpa::protocol::ResetCause::kWatchdog); }
void HardFault_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }
void MemManage_Handler() { SafeAndReset(palpa::protocol::ResetCause::kFaultHandler); }  // stack guard
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
    nullptr, nullptr, nullptr, nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // debug monitor
    nullptr,
    Default_Handler,  // PendSV
    SysTick_Handler,
    Uart0Rx_Handler,  // IRQ 0: UART0 receive
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler,
};

}  // extern "C"
