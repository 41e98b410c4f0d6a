// The bootloader's vector table and reset: nothing but the runtime start; every fault resets
// (the bootloader holds no state a reset could lose: the boot state is in flash).
#include <cstdint>

#include "../../boards/common/cortex_m_runtime.h"
#include "palpa/hal/mps2/registers.h"

extern "C" {

void Reset_Handler() { palpa::boards::StartRuntimeAndMain(); }
void NMI_Handler() { palpa::hal::mps2::SystemReset(); }
void HardFault_Handler() { palpa::hal::mps2::SystemReset(); }
void MemManage_Handler() { palpa::hal::mps2::SystemReset(); }
void BusFault_Handler() { palpa::hal::mps2::SystemReset(); }
void UsageFault_Handler() { palpa::hal::mps2::SystemReset(); }
void Default_Handler() { palpa::hal::mps2::SystemReset(); }
void Uart0Rx_Handler();

__attribute__((section(".isr_vector"), used)) void (*const g_vectors[16 + 1])() = {
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
    Default_Handler,  // SysTick: not used here
    Uart0Rx_Handler,  // IRQ 0: UART0 receive (recovery mode)
};

}  // extern "C"
