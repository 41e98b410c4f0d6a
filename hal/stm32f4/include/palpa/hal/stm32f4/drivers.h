// STM32F4 drivers behind the hal interfaces: clocks, DWT microsecond clock, USART1 with DMA,
// two AD5724R SPI DACs (8 channels, 0–10 V, hardware clear), ADC1 scanning 8 sensors by DMA,
// GPIO pins, independent watchdog, and the internal flash sectors that hold the configuration.
// Pin map and wiring: docs/stm32f4.md.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/byte_link.h"
#include "palpa/hal/clock.h"
#include "palpa/hal/digital_io.h"
#include "palpa/hal/flash.h"
#include "palpa/hal/stm32f4/registers.h"
#include "palpa/hal/watchdog.h"

namespace palpa::hal::stm32f4 {

/// 8 MHz crystal → 168 MHz core; flash wait states and caches first. Call once, from reset.
void ConfigureClocks();
/// Sets the brown-out reset to its highest threshold (2.70 V) if the option bytes say otherwise.
/// Programs the option bytes once in the board's life; returns true if it had to.
bool EnsureBrownOutLevel();
/// The reset cause flags of RCC_CSR, read once and cleared.
uint32_t TakeResetFlags();

/// Microseconds from the DWT cycle counter, widened to 64 bits on every read. No interrupt: the
/// clock keeps counting while a flash erase stalls the core (the main loop reads it far more
/// often than the 25 s the 32-bit counter takes to wrap).
class CycleClock final : public Clock {
 public:
  void Init();

 private:
  uint64_t DoNowMicros() override;
  uint32_t last_ = 0;
  uint64_t high_ = 0;
};

class GpioOutput final : public DigitalOutput {
 public:
  GpioOutput(GpioRegs* port, uint8_t pin) : port_(port), pin_(pin) {}
  void Init(bool initial_level);

 private:
  Status DoSet(bool level) override;
  GpioRegs* port_;
  uint8_t pin_;
};

/// A pulled-up input; `asserted_high` says which level means "asserted".
class GpioInput final : public DigitalInput {
 public:
  GpioInput(GpioRegs* port, uint8_t pin, bool asserted_high)
      : port_(port), pin_(pin), asserted_high_(asserted_high) {}
  void Init();

 private:
  bool DoRead() override;
  GpioRegs* port_;
  uint8_t pin_;
  bool asserted_high_;
};

/// USART1 (PA9 TX, PA10 RX) at 1 Mbaud 8N1. Receive: DMA2 stream 2 into a circular ring, no
/// interrupt per byte. Transmit: a ring drained by DMA2 stream 7 in contiguous chunks.
class DmaUart final : public ByteLink {
 public:
  static constexpr size_t kRxSize = 1024;  ///< reported to the host as the receive buffer
  static constexpr size_t kTxSize = 2048;
  static constexpr uint32_t kBaud = 1000000u;
  void Init();
  /// Starts the next transmit chunk when the previous one is done; call from the main loop.
  void PumpTx();

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override;
  size_t DoWrite(const uint8_t* data, size_t size) override;
  size_t DoWriteSpace() const override;

  uint8_t rx_[kRxSize];
  uint32_t rx_tail_ = 0;
  uint8_t tx_[kTxSize];
  uint32_t tx_head_ = 0, tx_tail_ = 0;
  uint32_t tx_in_flight_ = 0;  ///< bytes handed to the DMA, freed when it completes
};

/// Two AD5724R quad 12-bit DACs on SPI1 (PA5 SCK, PA7 MOSI; SYNC on PA4 and PB0), each output
/// on its +10 V range: channel i is DAC i / 4, output i % 4. CLR (PB1, active low, pulled low on
/// the board) holds every output at 0 V until Init releases it, and again from a fault handler.
class Ad5724Dacs final : public AnalogOutput {
 public:
  static constexpr uint8_t kChannels = 8;
  /// Powers the outputs up on their 0–10 V range, writes 0 V everywhere, then releases CLR.
  void Init();
  /// Drives CLR low: every output to 0 V in hardware. Safe to call from any fault handler.
  static void ClearAllOutputs();

 private:
  Status DoWrite(uint8_t channel, uint32_t counts) override;
  AnalogOutputSpec DoSpec(uint8_t channel) const override;
  void Send(uint8_t chip, uint32_t frame);
};

/// ADC1 scanning eight sensor inputs (PA0–PA3, PC0–PC3) continuously into memory by DMA2
/// stream 0. The 12-bit conversions are reported on the 14-bit scale of the board
/// configurations (× 4), so the same sensor counts serve the HSC digital and analogue variants.
class ScanAdc final : public AnalogInput {
 public:
  static constexpr uint8_t kChannels = 8;
  void Init();

 private:
  Result<uint32_t> DoRead(uint8_t channel) override;
  void DoReadAll(uint32_t* counts, uint8_t count) override;
  uint8_t DoBits() const override { return 14; }
  volatile uint16_t samples_[kChannels] = {};
};

/// The independent watchdog on the 32 kHz LSI: runs even if the main clock fails, and once
/// started cannot be stopped. 1–1 000 ms.
class IndependentWatchdog final : public Watchdog {
 private:
  void DoStart(uint32_t timeout_ms) override;
  void DoKick() override;
};

/// Flash sectors 1 and 2 (16 KiB each at 0x08004000), kept out of the image by the linker script,
/// for the two configuration copies. Erasing stalls instruction fetches from flash for up to
/// ~0.5 s, so the wait runs from RAM and keeps the watchdog fed; the pulsing enables stop
/// meanwhile, so the valves fall safe for the duration.
class InternalFlash final : public Flash {
 public:
  static constexpr uint32_t kBase = 0x08004000u;
  static constexpr uint32_t kSectorSize = 16384u;
  static constexpr uint8_t kFirstSector = 1;

 private:
  Status DoErase(uint32_t offset) override;
  Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override;
  Status DoRead(uint32_t offset, uint8_t* out, size_t size) override;
  uint32_t DoSectorSize() const override { return kSectorSize; }
  uint32_t DoSize() const override { return 2 * kSectorSize; }
};

}  // namespace palpa::hal::stm32f4
