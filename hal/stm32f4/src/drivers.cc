// STM32F4 register-level drivers (RM0090; AD5724R data sheet Rev. E for the DAC frames).
#include "palpa/hal/stm32f4/drivers.h"

#include <atomic>

namespace palpa::hal::stm32f4 {
namespace {

enum class PinMode : uint32_t { kInput = 0, kOutput = 1, kAlternate = 2, kAnalog = 3 };
enum class Pull : uint32_t { kNone = 0, kUp = 1, kDown = 2 };

void ConfigurePin(GpioRegs* port, uint8_t pin, PinMode mode, Pull pull = Pull::kNone,
                  uint32_t alternate = 0) {
  const uint32_t shift2 = pin * 2u;
  port->PUPDR = (port->PUPDR & ~(3u << shift2)) | (static_cast<uint32_t>(pull) << shift2);
  port->OSPEEDR |= 2u << shift2;  // fast: SPI at 21 MHz, USART at 1 Mbaud
  Reg& afr = port->AFR[pin / 8];
  const uint32_t shift4 = (pin % 8u) * 4u;
  afr = (afr & ~(0xFu << shift4)) | (alternate << shift4);
  port->MODER = (port->MODER & ~(3u << shift2)) | (static_cast<uint32_t>(mode) << shift2);
}

void WaitUntil(Reg& reg, uint32_t mask) {
  while ((reg & mask) == 0) {
  }
}

// DMA stream configuration bits (RM0090 §10.5.5).
constexpr uint32_t kDmaEnable = 1u << 0, kDmaMemToPeriph = 1u << 6, kDmaCircular = 1u << 8,
                   kDmaMemInc = 1u << 10;
constexpr uint32_t kDmaHalfWords = (1u << 11) | (1u << 13);
constexpr uint32_t DmaChannel(uint32_t n) { return n << 25; }

// AD5724R input shift register: R/W̄, 0, REG[2:0], A[2:0], 16 data bits.
constexpr uint32_t kDacRegData = 0u << 19, kDacRegRange = 1u << 19, kDacRegPower = 2u << 19;
constexpr uint32_t kDacAllChannels = 4u << 16;
constexpr uint32_t kDacRange0To10V = 1u;
constexpr uint32_t kDacPowerUpAll = 0x1Fu;  // PUA..PUD and PUREF (the internal 2.5 V reference)
constexpr uint8_t kDacClearPin = 1;         // PB1

}  // namespace

void ConfigureClocks() {
  kRcc->CR |= rcc::kCrHseOn;
  WaitUntil(kRcc->CR, rcc::kCrHseRdy);
  // VCO in = 8 MHz / M(8) = 1 MHz; VCO = ×N(336); SYSCLK = /P(2) = 168 MHz; USB = /Q(7) = 48 MHz.
  kRcc->PLLCFGR = 8u | (336u << 6) | (0u << 16) | (1u << 22) | (7u << 24);
  kRcc->CR |= rcc::kCrPllOn;
  WaitUntil(kRcc->CR, rcc::kCrPllRdy);
  kFlash->ACR =
      5u | (1u << 8) | (1u << 9) | (1u << 10);  // 5 wait states at 3.3 V; prefetch, caches
  kRcc->CFGR = (0u << 4) | (5u << 10) | (4u << 13) | 2u;  // AHB /1, APB1 /4, APB2 /2, PLL
  while ((kRcc->CFGR & (3u << 2)) != (2u << 2)) {
  }
}

bool EnsureBrownOutLevel() {
  if ((kFlash->OPTCR & flash::kOptBorMask) == flash::kOptBorLevel3) return false;
  kFlash->OPTKEYR = flash::kOptKey1;
  kFlash->OPTKEYR = flash::kOptKey2;
  kFlash->OPTCR = (kFlash->OPTCR & ~flash::kOptBorMask) | flash::kOptBorLevel3;
  kFlash->OPTCR |= flash::kOptStrt;
  while (kFlash->SR & flash::kSrBusy) {
  }
  kFlash->OPTCR |= flash::kOptLock;
  return true;
}

uint32_t TakeResetFlags() {
  const uint32_t flags = kRcc->CSR;
  kRcc->CSR |= rcc::kCsrRmvf;
  return flags;
}

void CycleClock::Init() {
  *kDemcr |= 1u << 24;  // TRCENA: the DWT runs
  *kDwtCyccnt = 0;
  *kDwtCtrl |= 1u;  // CYCCNTENA
}

uint64_t CycleClock::DoNowMicros() {
  const uint32_t now = *kDwtCyccnt;
  high_ += static_cast<uint32_t>(now - last_);  // wraps correctly across the 32-bit boundary
  last_ = now;
  return high_ / (kSysClockHz / 1000000u);
}

void GpioOutput::Init(bool initial_level) {
  DoSet(initial_level);  // the level first, so the pin never glitches to the other one
  ConfigurePin(port_, pin_, PinMode::kOutput);
}

// A write to BSRR cannot fail: the pin's driver takes the level.
Status GpioOutput::DoSet(bool level) {
  port_->BSRR = level ? (1u << pin_) : (1u << (pin_ + 16u));
  return Status::kOk;
}

void GpioInput::Init() { ConfigurePin(port_, pin_, PinMode::kInput, Pull::kUp); }

bool GpioInput::DoRead() { return ((port_->IDR >> pin_) & 1u) == (asserted_high_ ? 1u : 0u); }

void DmaUart::Init() {
  kRcc->AHB1ENR |= rcc::kAhb1GpioA | rcc::kAhb1Dma2;
  kRcc->APB2ENR |= rcc::kApb2Usart1;
  ConfigurePin(kGpioA, 9, PinMode::kAlternate, Pull::kNone, 7);
  ConfigurePin(kGpioA, 10, PinMode::kAlternate, Pull::kUp, 7);
  kUsart1->BRR = (kApb2Hz + kBaud / 2) / kBaud;  // oversampling by 16: BRR = f / baud
  kUsart1->CR3 = (1u << 6) | (1u << 7);          // DMAR, DMAT
  DmaStreamRegs& rx = kDma2->S[2];               // USART1_RX: DMA2 stream 2, channel 4
  rx.CR = 0;
  rx.PAR = reinterpret_cast<uint32_t>(&kUsart1->DR);
  rx.M0AR = reinterpret_cast<uint32_t>(rx_);
  rx.NDTR = kRxSize;
  rx.CR = DmaChannel(4) | kDmaMemInc | kDmaCircular | kDmaEnable;
  kUsart1->CR1 = (1u << 13) | (1u << 3) | (1u << 2);  // UE, TE, RE
}

size_t DmaUart::DoRead(uint8_t* out, size_t capacity) {
  // The DMA's write position is kRxSize - NDTR. A host that overruns the ring loses bytes; the
  // frame CRC catches it and the reliable channel resends (flow control keeps that rare).
  const uint32_t head = (kRxSize - kDma2->S[2].NDTR) % kRxSize;
  std::atomic_signal_fence(std::memory_order_acquire);  // bytes read after the count
  size_t n = 0;
  while (n < capacity && rx_tail_ != head) {
    out[n++] = rx_[rx_tail_];
    rx_tail_ = (rx_tail_ + 1) % kRxSize;
  }
  return n;
}

size_t DmaUart::DoWriteSpace() const {
  return kTxSize - 1 - (tx_head_ + kTxSize - tx_tail_) % kTxSize;
}

size_t DmaUart::DoWrite(const uint8_t* data, size_t size) {
  const size_t n = size < DoWriteSpace() ? size : DoWriteSpace();
  for (size_t i = 0; i < n; ++i) {
    tx_[tx_head_] = data[i];
    tx_head_ = (tx_head_ + 1) % kTxSize;
  }
  return n;
}

void DmaUart::PumpTx() {
  DmaStreamRegs& tx = kDma2->S[7];  // USART1_TX: DMA2 stream 7, channel 4
  if (tx_in_flight_ != 0) {
    if ((kDma2->HISR & (1u << 27)) == 0) return;  // TCIF7: the chunk is not done yet
    kDma2->HIFCR = 0x3Du << 22;                   // clear stream 7's flags
    tx_tail_ = (tx_tail_ + tx_in_flight_) % kTxSize;
    tx_in_flight_ = 0;
  }
  if (tx_tail_ == tx_head_) return;
  const uint32_t chunk =
      tx_head_ > tx_tail_ ? tx_head_ - tx_tail_ : kTxSize - tx_tail_;  // contiguous
  tx.CR = 0;
  while (tx.CR & kDmaEnable) {
  }
  tx.PAR = reinterpret_cast<uint32_t>(&kUsart1->DR);
  tx.M0AR = reinterpret_cast<uint32_t>(&tx_[tx_tail_]);
  tx.NDTR = chunk;
  tx_in_flight_ = chunk;
  asm volatile("dmb" ::: "memory");  // the queued bytes are in RAM before the DMA reads them
  tx.CR = DmaChannel(4) | kDmaMemInc | kDmaMemToPeriph | kDmaEnable;
}

void Ad5724Dacs::Init() {
  kRcc->AHB1ENR |= rcc::kAhb1GpioA | rcc::kAhb1GpioB;
  kRcc->APB2ENR |= rcc::kApb2Spi1;
  ClearAllOutputs();  // CLR low while the DACs are set up
  GpioOutput sync0(kGpioA, 4), sync1(kGpioB, 0);
  sync0.Init(true);
  sync1.Init(true);
  ConfigurePin(kGpioA, 5, PinMode::kAlternate, Pull::kNone, 5);
  ConfigurePin(kGpioA, 7, PinMode::kAlternate, Pull::kNone, 5);
  // Master, 84 MHz / 4 = 21 MHz (AD5724R: ≤ 30 MHz), CPOL 0 / CPHA 1 (data taken on the falling
  // edge), 8-bit frames, software slave select.
  kSpi1->CR1 = (1u << 0) | (1u << 2) | (1u << 3) | (1u << 8) | (1u << 9);
  kSpi1->CR1 |= 1u << 6;  // SPE
  for (uint8_t chip = 0; chip < 2; ++chip) {
    Send(chip, kDacRegPower | kDacPowerUpAll);
    Send(chip, kDacRegRange | kDacAllChannels | kDacRange0To10V);
    Send(chip, kDacRegData | kDacAllChannels | 0u);
  }
  GpioOutput clear(kGpioB, kDacClearPin);
  clear.Init(true);  // release CLR: the outputs now follow their registers (0 V)
}

void Ad5724Dacs::ClearAllOutputs() {
  kRcc->AHB1ENR |= rcc::kAhb1GpioB;
  kGpioB->BSRR = 1u << (kDacClearPin + 16u);
  kGpioB->MODER = (kGpioB->MODER & ~(3u << (kDacClearPin * 2u))) | (1u << (kDacClearPin * 2u));
}

void Ad5724Dacs::Send(uint8_t chip, uint32_t frame) {
  GpioRegs* const port = chip == 0 ? kGpioA : kGpioB;
  const uint8_t pin = chip == 0 ? 4 : 0;
  port->BSRR = 1u << (pin + 16u);  // SYNC low
  for (int shift = 16; shift >= 0; shift -= 8) {
    WaitUntil(kSpi1->SR, 1u << 1);  // TXE
    kSpi1->DR = (frame >> shift) & 0xFFu;
  }
  WaitUntil(kSpi1->SR, 1u << 1);
  while (kSpi1->SR & (1u << 7)) {  // BSY: the last bit is out
  }
  (void)kSpi1->DR;  // drop what MISO shifted in, so no overrun flag lingers
  (void)kSpi1->SR;
  port->BSRR = 1u << pin;  // SYNC high: the DAC latches the frame (LDAC tied low)
}

Status Ad5724Dacs::DoWrite(uint8_t channel, uint32_t counts) {
  if (channel >= kChannels || counts > 0xFFFu) return Status::kOutOfRange;
  Send(channel / 4u, kDacRegData | (static_cast<uint32_t>(channel % 4u) << 16) |
                         (counts << 4));  // 12 bits, left-aligned
  return Status::kOk;
}

AnalogOutputSpec Ad5724Dacs::DoSpec(uint8_t) const {
  return AnalogOutputSpec{12, SignalRange::kVolt0To10};
}

void ScanAdc::Init() {
  kRcc->AHB1ENR |= rcc::kAhb1GpioA | rcc::kAhb1GpioC | rcc::kAhb1Dma2;
  kRcc->APB2ENR |= rcc::kApb2Adc1;
  for (uint8_t pin = 0; pin < 4; ++pin) {
    ConfigurePin(kGpioA, pin, PinMode::kAnalog);  // ADC1_IN0..3
    ConfigurePin(kGpioC, pin, PinMode::kAnalog);  // ADC1_IN10..13
  }
  kAdcCommon->CCR = 1u << 16;            // ADC clock 84 MHz / 4 = 21 MHz
  kAdc1->SMPR1 = 0x00000924u;            // IN10..13: 84 cycles (0b100 each)
  kAdc1->SMPR2 = 0x00000924u;            // IN0..3: 84 cycles
  kAdc1->SQR1 = (kChannels - 1u) << 20;  // 8 conversions
  kAdc1->SQR3 = 0u | (1u << 5) | (2u << 10) | (3u << 15) | (10u << 20) | (11u << 25);
  kAdc1->SQR2 = 12u | (13u << 5);
  kAdc1->CR1 = 1u << 8;              // SCAN
  DmaStreamRegs& dma = kDma2->S[0];  // ADC1: DMA2 stream 0, channel 0
  dma.CR = 0;
  dma.PAR = reinterpret_cast<uint32_t>(&kAdc1->DR);
  dma.M0AR = reinterpret_cast<uint32_t>(samples_);
  dma.NDTR = kChannels;
  dma.CR = DmaChannel(0) | kDmaHalfWords | kDmaMemInc | kDmaCircular | kDmaEnable;
  kAdc1->CR2 = (1u << 0) | (1u << 1) | (1u << 8) | (1u << 9);  // ADON, CONT, DMA, DDS
  kAdc1->CR2 |= 1u << 30;                                      // SWSTART
}

Result<uint32_t> ScanAdc::DoRead(uint8_t channel) {
  if (channel >= kChannels) return Status::kNotFound;
  if (kAdc1->SR & (1u << 5)) return Status::kIoError;  // OVR: the scan stopped; readings are stale
  return static_cast<uint32_t>(samples_[channel]) << 2;
}

void ScanAdc::DoReadAll(uint32_t* counts, uint8_t count) {
  const bool overrun = (kAdc1->SR & (1u << 5)) != 0;  // one status read for the whole scan
  for (uint8_t i = 0; i < count; ++i) {
    counts[i] =
        overrun || i >= kChannels ? kConversionFailed : static_cast<uint32_t>(samples_[i]) << 2;
  }
}

void IndependentWatchdog::DoStart(uint32_t timeout_ms) {
  const uint32_t ms = timeout_ms < 1 ? 1 : (timeout_ms > 1000 ? 1000 : timeout_ms);
  kIwdg->KR = 0xCCCCu;  // start (also starts the LSI)
  kIwdg->KR = 0x5555u;  // unlock PR and RLR
  kIwdg->PR = 1u;       // LSI 32 kHz / 8 = 4 kHz
  kIwdg->RLR = ms * 4u;
  while (kIwdg->SR != 0) {
  }
  kIwdg->KR = 0xAAAAu;
}

void IndependentWatchdog::DoKick() { kIwdg->KR = 0xAAAAu; }

}  // namespace palpa::hal::stm32f4
