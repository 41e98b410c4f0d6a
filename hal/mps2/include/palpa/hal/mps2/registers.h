// Register definitions of the MPS2 AN386 (Cortex-M4 on the MPS2 board) peripherals palpa uses:
// CMSDK APB UART and watchdog, and the Cortex-M core's SysTick, NVIC, SCB and MPU. Names follow
// the CMSDK and ARMv7-M reference manuals. Kept out of portable code.
#pragma once

#include <cstdint>

namespace palpa::hal::mps2 {

struct CmsdkUart {
  volatile uint32_t DATA;       // 0x00
  volatile uint32_t STATE;      // 0x04: bit0 TX buffer full, bit1 RX buffer full
  volatile uint32_t CTRL;       // 0x08: bit0 TX enable, bit1 RX enable, bit2 TX int, bit3 RX int
  volatile uint32_t INTSTATUS;  // 0x0C read; INTCLEAR on write
  volatile uint32_t BAUDDIV;    // 0x10
};
inline constexpr uint32_t kUartStateTxFull = 1u << 0;
inline constexpr uint32_t kUartStateRxFull = 1u << 1;
inline constexpr uint32_t kUartCtrlTxEnable = 1u << 0;
inline constexpr uint32_t kUartCtrlRxEnable = 1u << 1;
inline constexpr uint32_t kUartCtrlRxInterrupt = 1u << 3;
inline constexpr uint32_t kUartIntRx = 1u << 1;

struct CmsdkWatchdog {
  volatile uint32_t LOAD;    // 0x000
  volatile uint32_t VALUE;   // 0x004
  volatile uint32_t CTRL;    // 0x008: bit0 INTEN, bit1 RESEN
  volatile uint32_t INTCLR;  // 0x00C: any write clears the interrupt and reloads
  volatile uint32_t RIS;     // 0x010
  volatile uint32_t MIS;     // 0x014
  uint32_t reserved[762];
  volatile uint32_t LOCK;  // 0xC00
};
inline constexpr uint32_t kWatchdogUnlock = 0x1ACCE551u;

struct SysTickRegs {
  volatile uint32_t CSR;  // bit0 ENABLE, bit1 TICKINT, bit2 CLKSOURCE, bit16 COUNTFLAG
  volatile uint32_t RVR;
  volatile uint32_t CVR;
  volatile uint32_t CALIB;
};

inline CmsdkUart* const kUart0 = reinterpret_cast<CmsdkUart*>(0x40004000u);
inline CmsdkWatchdog* const kWatchdog = reinterpret_cast<CmsdkWatchdog*>(0x40008000u);
inline SysTickRegs* const kSysTick = reinterpret_cast<SysTickRegs*>(0xE000E010u);
inline volatile uint32_t* const kNvicIser0 = reinterpret_cast<volatile uint32_t*>(0xE000E100u);
inline volatile uint32_t* const kScbIcsr = reinterpret_cast<volatile uint32_t*>(0xE000ED04u);
inline constexpr uint32_t kIcsrPendSysTick = 1u << 26;
inline volatile uint32_t* const kScbVtor = reinterpret_cast<volatile uint32_t*>(0xE000ED08u);
inline volatile uint32_t* const kNvicIcer0 = reinterpret_cast<volatile uint32_t*>(0xE000E180u);
inline volatile uint32_t* const kNvicIcpr0 = reinterpret_cast<volatile uint32_t*>(0xE000E280u);
inline volatile uint32_t* const kScbAircr = reinterpret_cast<volatile uint32_t*>(0xE000ED0Cu);
inline volatile uint32_t* const kScbShcsr = reinterpret_cast<volatile uint32_t*>(0xE000ED24u);
inline volatile uint32_t* const kScbCpacr = reinterpret_cast<volatile uint32_t*>(0xE000ED88u);
inline volatile uint32_t* const kMpuCtrl = reinterpret_cast<volatile uint32_t*>(0xE000ED94u);
inline volatile uint32_t* const kMpuRbar = reinterpret_cast<volatile uint32_t*>(0xE000ED9Cu);
inline volatile uint32_t* const kMpuRasr = reinterpret_cast<volatile uint32_t*>(0xE000EDA0u);

inline constexpr uint32_t kSysClockHz = 25000000u;  // MPS2 FPGA image SYSCLK
inline constexpr uint32_t kUart0RxIrq = 0;

/// Requests a system reset (AIRCR.SYSRESETREQ); never returns.
[[noreturn]] inline void SystemReset() {
  // Every store before this (a reset record) must reach RAM first: the clobber keeps the compiler
  // from dropping or sinking it past the reset, the DSB drains the write buffer (as CMSIS does).
  asm volatile("dsb" ::: "memory");
  *kScbAircr = (0x5FAu << 16) | (1u << 2);
  for (;;) {
  }
}

}  // namespace palpa::hal::mps2
