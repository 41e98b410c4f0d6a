// A firmware update against the simulated NOR flash, start to finish, as the board's update
// engine and bootloader run it — with a power cut at any byte. Used by the boot tests (a hundred
// cuts) and the benchmark (a thousand).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "development_signer.h"
#include "palpa/core/boot_state.h"
#include "palpa/core/update_engine.h"
#include "palpa/hal/fake/simulated_nor_flash.h"
#include "palpa/host/firmware_image.h"

namespace palpa::testing {

/// A release: the images of both slots, with a body of `body_size` random bytes, signed by
/// `signer` (the development key the simulated board trusts; nullptr: unsigned).
host::UpdatePackage MakeRelease(uint8_t major, uint8_t minor, uint32_t rollback_counter,
                                uint32_t body_size, uint32_t seed,
                                protocol::BoardKind kind = protocol::BoardKind::kSim,
                                protocol::ImageSigner* signer = &DevelopmentSigner());

/// A board as it leaves the factory: release 1.0 in slot 0, first boot done (confirmed).
struct UpdateWorld {
  explicit UpdateWorld(uint32_t seed);
  hal::fake::SimulatedNorFlash flash;
  core::FlashLayout layout = core::kDefaultLayout;
  protocol::BoardKind kind = protocol::BoardKind::kSim;
  uint8_t running = 0;  ///< the slot the last boot chose (kNoSlot: recovery)
  core::BootDecision last_boot{};
  /// Resets the board: the bootloader's choice, saved state and all.
  core::BootDecision Reboot();
};

/// The update a host performs over the link, step by step through the engine: enter, erase the
/// image's sectors, write in 240-byte chunks, check the hash, activate, reboot, confirm. Stops
/// at the first failure (a power cut makes every flash operation fail) with its step's name.
struct UpdateOutcome {
  bool completed = false;
  std::string failed_step;
};
/// The engines run on `engine_flash` (default: the world's flash) with `watchdog` (default none);
/// the bootloader's reboot between activation and confirmation always reads the world's flash.
UpdateOutcome RunUpdate(UpdateWorld& world, const host::UpdatePackage& release, bool confirm = true,
                        hal::Watchdog* watchdog = nullptr, hal::Flash* engine_flash = nullptr);

/// One power cut: a fresh board, the update with the power failing after `cut_after` flash
/// bytes, power back, boot. What booted, and whether it was the old release or the new.
struct CutOutcome {
  bool valid = false;   ///< the booted slot holds an image that checks
  bool is_new = false;  ///< it is the update's release
  std::string phase;    ///< where the cut fell
  core::BootReason reason = core::BootReason::kRecovery;
};
CutOutcome CutPowerDuringUpdate(uint64_t cut_after, uint32_t seed);

/// Flash bytes a whole update touches (the range cut points are drawn from).
uint64_t UpdateFlashBytes(uint32_t seed);

}  // namespace palpa::testing
