// MPS2 drivers behind the hal interfaces: CMSDK UART (interrupt-driven receive into a ring,
// non-blocking transmit), SysTick clock at 1 kHz from the 25 MHz system clock, CMSDK watchdog.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/watchdog.h"

namespace palpa::hal::mps2 {

class Uart final : public ByteLink {
 public:
  static constexpr size_t kRxSize = 1024;  ///< reported to the host as the receive buffer
  static constexpr size_t kTxSize = 2048;
  void Init();
  /// The receive interrupt: clears the interrupt first (or the CMSDK UART stalls), then drains.
  void OnRxInterrupt();
  /// Moves queued bytes into the transmitter while it has room; call from the main loop.
  void PumpTx();
  /// Sends everything queued, then lets the last character leave the shifter: before a reset.
  /// Bounded by the line rate (a full ring is 13 ms at 1.56 Mbaud), not by a guess.
  void DrainTx();
  uint32_t rx_overruns() const { return rx_overruns_; }
  /// Puts bytes into the receive ring as if they had arrived (the benchmark image's host).
  void Inject(const uint8_t* data, size_t size) {
    for (size_t i = 0; i < size; ++i) {
      const uint32_t next = (rx_head_ + 1) % kRxSize;
      if (next == rx_tail_) return;
      rx_[rx_head_] = data[i];
      rx_head_ = next;
    }
  }

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override;
  size_t DoWrite(const uint8_t* data, size_t size) override;
  size_t DoWriteSpace() const override;

  uint8_t rx_[kRxSize] = {};
  volatile uint32_t rx_head_ = 0;  ///< written by the interrupt
  uint32_t rx_tail_ = 0;
  uint8_t tx_[kTxSize] = {};
  uint32_t tx_head_ = 0, tx_tail_ = 0;
  volatile uint32_t rx_overruns_ = 0;
};

class SysTickClock final : public Clock {
 public:
  void Init();
  void OnTick() { millis_ = millis_ + 1; }

 private:
  uint64_t DoNowMicros() override;
  volatile uint64_t millis_ = 0;
};

class CmsdkWatchdogDriver final : public Watchdog {
 private:
  void DoStart(uint32_t timeout_ms) override;
  void DoKick() override;
};

}  // namespace palpa::hal::mps2
