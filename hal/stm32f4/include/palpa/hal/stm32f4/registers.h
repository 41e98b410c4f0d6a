// STM32F405/407 peripheral registers used by the board (addresses and bits from RM0090 rev 19)
// and the Cortex-M4 core registers it touches. Kept out of portable code: only hal/stm32f4 and
// firmware/boards/stm32f4 include this.
#pragma once

#include <cstdint>

namespace palpa::hal::stm32f4 {

using Reg = volatile uint32_t;

struct RccRegs {  // RM0090 §7.3
  Reg CR, PLLCFGR, CFGR, CIR, AHB1RSTR, AHB2RSTR, AHB3RSTR, reserved0, APB1RSTR, APB2RSTR,
      reserved1[2], AHB1ENR, AHB2ENR, AHB3ENR, reserved2, APB1ENR, APB2ENR, reserved3[2], AHB1LPENR,
      AHB2LPENR, AHB3LPENR, reserved4, APB1LPENR, APB2LPENR, reserved5[2], BDCR, CSR;
};
struct FlashRegs {
  Reg ACR, KEYR, OPTKEYR, SR, CR, OPTCR;
};  // §3.9
struct GpioRegs {
  Reg MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR, BSRR, LCKR, AFR[2];
};  // §8.4
struct UsartRegs {
  Reg SR, DR, BRR, CR1, CR2, CR3, GTPR;
};  // §30.6
struct SpiRegs {
  Reg CR1, CR2, SR, DR, CRCPR, RXCRCR, TXCRCR, I2SCFGR, I2SPR;
};                // §28.5
struct AdcRegs {  // §13.13
  Reg SR, CR1, CR2, SMPR1, SMPR2, JOFR[4], HTR, LTR, SQR1, SQR2, SQR3, JSQR, JDR[4], DR;
};
struct AdcCommonRegs {
  Reg CSR, CCR, CDR;
};
struct DmaStreamRegs {
  Reg CR, NDTR, PAR, M0AR, M1AR, FCR;
};  // §10.5
struct DmaRegs {
  Reg LISR, HISR, LIFCR, HIFCR;
  DmaStreamRegs S[8];
};
struct IwdgRegs {
  Reg KR, PR, RLR, SR;
};  // §21.4

inline RccRegs* const kRcc = reinterpret_cast<RccRegs*>(0x40023800u);
inline FlashRegs* const kFlash = reinterpret_cast<FlashRegs*>(0x40023C00u);
inline GpioRegs* const kGpioA = reinterpret_cast<GpioRegs*>(0x40020000u);
inline GpioRegs* const kGpioB = reinterpret_cast<GpioRegs*>(0x40020400u);
inline GpioRegs* const kGpioC = reinterpret_cast<GpioRegs*>(0x40020800u);
inline UsartRegs* const kUsart1 = reinterpret_cast<UsartRegs*>(0x40011000u);
inline SpiRegs* const kSpi1 = reinterpret_cast<SpiRegs*>(0x40013000u);
inline AdcRegs* const kAdc1 = reinterpret_cast<AdcRegs*>(0x40012000u);
inline AdcCommonRegs* const kAdcCommon = reinterpret_cast<AdcCommonRegs*>(0x40012300u);
inline DmaRegs* const kDma2 = reinterpret_cast<DmaRegs*>(0x40026400u);
inline IwdgRegs* const kIwdg = reinterpret_cast<IwdgRegs*>(0x40003000u);

// Cortex-M4 core (ARMv7-M ARM): SysTick, SCB, MPU, DWT cycle counter.
inline Reg* const kScbAircr = reinterpret_cast<Reg*>(0xE000ED0Cu);
inline Reg* const kScbShcsr = reinterpret_cast<Reg*>(0xE000ED24u);
inline Reg* const kScbCpacr = reinterpret_cast<Reg*>(0xE000ED88u);
inline Reg* const kDemcr = reinterpret_cast<Reg*>(0xE000EDFCu);
inline Reg* const kDwtCtrl = reinterpret_cast<Reg*>(0xE0001000u);
inline Reg* const kDwtCyccnt = reinterpret_cast<Reg*>(0xE0001004u);
inline Reg* const kMpuCtrl = reinterpret_cast<Reg*>(0xE000ED94u);
inline Reg* const kMpuRbar = reinterpret_cast<Reg*>(0xE000ED9Cu);
inline Reg* const kMpuRasr = reinterpret_cast<Reg*>(0xE000EDA0u);

// Clocks: 8 MHz crystal → PLL → 168 MHz core, APB1 42 MHz, APB2 84 MHz.
inline constexpr uint32_t kHseHz = 8000000u;
inline constexpr uint32_t kSysClockHz = 168000000u;
inline constexpr uint32_t kApb2Hz = 84000000u;

namespace rcc {
inline constexpr uint32_t kCrHseOn = 1u << 16, kCrHseRdy = 1u << 17, kCrPllOn = 1u << 24,
                          kCrPllRdy = 1u << 25;
inline constexpr uint32_t kAhb1GpioA = 1u << 0, kAhb1GpioB = 1u << 1, kAhb1GpioC = 1u << 2,
                          kAhb1Dma2 = 1u << 22;
inline constexpr uint32_t kApb2Usart1 = 1u << 4, kApb2Adc1 = 1u << 8, kApb2Spi1 = 1u << 12;
// CSR reset flags (§7.3.21); RMVF clears them.
inline constexpr uint32_t kCsrLsiOn = 1u << 0, kCsrLsiRdy = 1u << 1, kCsrRmvf = 1u << 24;
inline constexpr uint32_t kCsrBor = 1u << 25, kCsrPin = 1u << 26, kCsrPor = 1u << 27,
                          kCsrSoftware = 1u << 28;
inline constexpr uint32_t kCsrIwdg = 1u << 29, kCsrWwdg = 1u << 30, kCsrLowPower = 1u << 31;
}  // namespace rcc

namespace flash {
inline constexpr uint32_t kKey1 = 0x45670123u, kKey2 = 0xCDEF89ABu;
inline constexpr uint32_t kOptKey1 = 0x08192A3Bu, kOptKey2 = 0x4C5D6E7Fu;
inline constexpr uint32_t kSrBusy = 1u << 16, kSrErrors = 0xF0u, kSrEop = 1u << 0;
inline constexpr uint32_t kCrPg = 1u << 0, kCrSer = 1u << 1, kCrStrt = 1u << 16, kCrLock = 1u << 31;
inline constexpr uint32_t kOptLock = 1u << 0, kOptStrt = 1u << 1, kOptBorMask = 3u << 2;
inline constexpr uint32_t kOptBorLevel3 = 0u << 2;  ///< reset below 2.70 V (the highest threshold)
}  // namespace flash

}  // namespace palpa::hal::stm32f4
