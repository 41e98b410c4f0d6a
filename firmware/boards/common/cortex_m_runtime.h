// The C++ runtime start every Cortex-M board shell runs from its reset handler, and the handler
// names its vector table uses.
#pragma once

#include <cstdint>

extern "C" {
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;  // from the linker script
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();
void Reset_Handler();
void NMI_Handler();
void HardFault_Handler();
void MemManage_Handler();
void BusFault_Handler();
void UsageFault_Handler();
void Default_Handler();
}

namespace palpa::boards {

/// FPU on (before any float instruction), .data copied from flash, .bss zeroed, static
/// constructors run, then main(). Runs after the board has made its outputs safe.
[[noreturn]] inline void StartRuntimeAndMain() {
  *reinterpret_cast<volatile uint32_t*>(0xE000ED88u) |= 0xFu << 20;  // CPACR: CP10, CP11
  asm volatile("dsb\n isb");
  const uint32_t* src = &_sidata;
  for (uint32_t* dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  for (auto* init = __init_array_start; init < __init_array_end; ++init) (*init)();
  main();
  for (;;) {
  }
}

}  // namespace palpa::boards
