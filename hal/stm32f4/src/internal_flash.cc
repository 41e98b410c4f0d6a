// The STM32F4's own flash as the board's NOR store (RM0090 §3): sectors erased and bytes programmed
// with the wait for the flash run from RAM, feeding the watchdog.
#include "palpa/hal/stm32f4/drivers.h"

namespace palpa::hal::stm32f4 {

namespace {

// Runs from RAM: while the flash is busy an instruction fetch from it would stall the core for
// the whole erase. The watchdog is fed meanwhile (nothing else runs; the outputs hold or fall
// safe).
[[gnu::section(".ramfunc"), gnu::noinline, gnu::long_call]] uint32_t WaitFlashFeedingWatchdog() {
  while (kFlash->SR & flash::kSrBusy) kIwdg->KR = 0xAAAAu;
  return kFlash->SR;
}

Status FinishFlashOperation() {
  const uint32_t sr = WaitFlashFeedingWatchdog();
  kFlash->SR = flash::kSrErrors | flash::kSrEop;  // write-1-to-clear
  kFlash->CR = flash::kCrLock;
  return (sr & flash::kSrErrors) ? Status::kIoError : Status::kOk;
}

void UnlockFlash() {
  if (kFlash->CR & flash::kCrLock) {
    kFlash->KEYR = flash::kKey1;
    kFlash->KEYR = flash::kKey2;
  }
}

}  // namespace

Status InternalFlash::DoErase(uint32_t offset) {
  if (offset % kSectorSize != 0 || offset >= DoSize()) return Status::kOutOfRange;
  UnlockFlash();
  const uint32_t sector = kFirstSector + offset / kSectorSize;
  kFlash->CR = flash::kCrSer | (sector << 3) | (2u << 8);  // sector erase, 32-bit parallelism
  kFlash->CR |= flash::kCrStrt;
  return FinishFlashOperation();
}

Status InternalFlash::DoProgram(uint32_t offset, const uint8_t* data, size_t size) {
  if (offset > DoSize() || size > DoSize() - offset) return Status::kOutOfRange;
  UnlockFlash();
  kFlash->CR = flash::kCrPg;  // byte parallelism: any length, any alignment
  for (size_t i = 0; i < size; ++i) {
    *reinterpret_cast<volatile uint8_t*>(kBase + offset + i) = data[i];
    while (kFlash->SR & flash::kSrBusy) {
    }
    if (kFlash->SR & flash::kSrErrors) break;
  }
  return FinishFlashOperation();
}

Status InternalFlash::DoRead(uint32_t offset, uint8_t* out, size_t size) {
  if (offset > DoSize() || size > DoSize() - offset) return Status::kOutOfRange;
  const auto* from = reinterpret_cast<const volatile uint8_t*>(kBase + offset);
  for (size_t i = 0; i < size; ++i) out[i] = from[i];
  return Status::kOk;
}

}  // namespace palpa::hal::stm32f4
