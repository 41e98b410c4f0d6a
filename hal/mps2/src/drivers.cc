// CMSDK UART, SysTick and CMSDK watchdog drivers for the MPS2 AN386.
#include "palpa/hal/mps2/drivers.h"

#include <atomic>

#include "palpa/hal/mps2/registers.h"

namespace palpa::hal::mps2 {

void Uart::Init() {
  kUart0->BAUDDIV = 16;  // the fastest the CMSDK UART allows; QEMU does not pace it
  kUart0->CTRL = kUartCtrlTxEnable | kUartCtrlRxEnable | kUartCtrlRxInterrupt;
  *kNvicIser0 = 1u << kUart0RxIrq;
}

void Uart::OnRxInterrupt() {
  kUart0->INTSTATUS = kUartIntRx;  // INTCLEAR before draining DATA, or RX stalls after a byte
  while (kUart0->STATE & kUartStateRxFull) {
    const uint8_t byte = static_cast<uint8_t>(kUart0->DATA);
    const uint32_t next = (rx_head_ + 1) % kRxSize;
    if (next == rx_tail_) {
      rx_overruns_ = rx_overruns_ + 1;  // full: the byte is lost; the frame's CRC will say so
      continue;
    }
    rx_[rx_head_] = byte;
    std::atomic_signal_fence(std::memory_order_release);  // the byte is in before the head moves
    rx_head_ = next;
  }
}

size_t Uart::DoRead(uint8_t* out, size_t capacity) {
  const uint32_t head = rx_head_;
  std::atomic_signal_fence(std::memory_order_acquire);  // bytes read after the head
  size_t n = 0;
  while (n < capacity && rx_tail_ != head) {
    out[n++] = rx_[rx_tail_];
    rx_tail_ = (rx_tail_ + 1) % kRxSize;
  }
  return n;
}

size_t Uart::DoWriteSpace() const {
  return kTxSize - 1 - (tx_head_ + kTxSize - tx_tail_) % kTxSize;
}

size_t Uart::DoWrite(const uint8_t* data, size_t size) {
  const size_t n = size < DoWriteSpace() ? size : DoWriteSpace();
  for (size_t i = 0; i < n; ++i) {
    tx_[tx_head_] = data[i];
    tx_head_ = (tx_head_ + 1) % kTxSize;
  }
  PumpTx();
  return n;
}

void Uart::PumpTx() {
  while (tx_tail_ != tx_head_ && !(kUart0->STATE & kUartStateTxFull)) {
    kUart0->DATA = tx_[tx_tail_];
    tx_tail_ = (tx_tail_ + 1) % kTxSize;
  }
}

void Uart::DrainTx() {
  while (tx_tail_ != tx_head_ || (kUart0->STATE & kUartStateTxFull)) PumpTx();
  // The CMSDK UART has no "shifter empty" flag: wait out one character (6.4 µs at BAUDDIV 16)
  // with margin, a register read being a few cycles.
  for (int i = 0; i < 256; ++i) (void)kUart0->STATE;
}

void SysTickClock::Init() {
  kSysTick->RVR = kSysClockHz / 1000u - 1u;
  kSysTick->CVR = 0;
  kSysTick->CSR = 0x7;  // processor clock, interrupt, enable
}

uint64_t SysTickClock::DoNowMicros() {
  // Read the millisecond count and the down-counter consistently across a wrap.
  uint64_t ms;
  uint32_t counter;
  bool pending;
  do {
    ms = millis_;
    counter = kSysTick->CVR;
    pending = (*kScbIcsr & kIcsrPendSysTick) != 0;
  } while (ms != millis_);
  const uint32_t reload = kSysTick->RVR + 1u;
  // The counter reloaded but its interrupt has not run yet: that millisecond has passed.
  if (pending && counter > reload / 2) ++ms;
  return ms * 1000u + (reload - counter) / (kSysClockHz / 1000000u);
}

void CmsdkWatchdogDriver::DoStart(uint32_t timeout_ms) {
  kWatchdog->LOCK = kWatchdogUnlock;
  // The first expiry raises the NMI (which writes safe codes and resets); RESEN resets on the
  // second in case the NMI handler itself cannot run.
  kWatchdog->LOAD = kSysClockHz / 1000u * timeout_ms;
  kWatchdog->CTRL = 0x3;
  kWatchdog->LOCK = 0;
}

void CmsdkWatchdogDriver::DoKick() {
  kWatchdog->LOCK = kWatchdogUnlock;
  kWatchdog->INTCLR = 1;
  kWatchdog->LOCK = 0;
}

}  // namespace palpa::hal::mps2
