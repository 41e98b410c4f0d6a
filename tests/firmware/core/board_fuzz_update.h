// The board fuzzer's firmware-update part: the image flash, update messages with fuzzed fields,
// and the checks that no message harms the bootloader, the running image or the boot state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "fuzz_input.h"
#include "palpa/core/boot_state.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/fake/simulated_nor_flash.h"

namespace palpa::testing {

/// Reports a broken guarantee and aborts, so libFuzzer keeps the input.
[[noreturn]] void BoardFuzzFail(const char* what, unsigned line);

/// Sends one reliable message (type, encoded body) to the board under test.
using SendMessage = std::function<void(uint8_t type, const uint8_t* body, size_t size)>;

class UpdateFuzzer {
 public:
  UpdateFuzzer();
  core::UpdateEngine& engine() { return engine_; }

  /// One update operation from the script: enter, erase, write (often where the last write
  /// ended), activate (with the SHA-256 of what the slot holds, so verification goes on to the
  /// image itself), confirm, or a whole well-formed image. Afterwards the bootloader and the
  /// running slot must be intact, and a message that marked a slot for a trial boot must have
  /// left there a valid image for this board that the rollback floor allows.
  void Send(FuzzInput& s, const SendMessage& send);

 private:
  void SendWholeImage(FuzzInput& s, uint8_t slot, const SendMessage& send);
  core::BootState BootStateNow();
  void CheckTrial(uint32_t sequence_before);
  bool ProtectedIntact() const;

  hal::fake::SimulatedNorFlash flash_;
  const bool boot_state_written_;  ///< before the engine, which reads it
  core::UpdateEngine engine_;
  std::vector<uint8_t> protected_bytes_;  ///< bootloader and slot 0 as they started
  uint32_t next_write_ = 0;               ///< where the last update write ended
};

}  // namespace palpa::testing
