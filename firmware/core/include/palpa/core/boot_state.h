// Boot state: which slot holds the good image, which one waits for (or is in) its one trial
// boot, and the anti-rollback floor — kept as write-once records in two alternating flash
// sectors, each with a sequence number and a CRC. Every change is one record write, so a power
// cut leaves the previous state or the new one, never a mixture.
#pragma once

#include <cstdint>

#include "palpa/core/flash_layout.h"
#include "palpa/hal/flash.h"
#include "palpa/hal/watchdog.h"
#include "palpa/protocol/image.h"

namespace palpa::core {

inline constexpr uint8_t kNoSlot = 0xFF;

enum class TrialState : uint8_t {
  kNone = 0,
  kPending = 1,  ///< activated: boot it once on the next reset
  kBooting = 2,  ///< the bootloader started it; a reset before confirmation reverts
};

struct BootState {
  uint32_t sequence = 0;  ///< 0: no record yet (a fresh board)
  uint8_t confirmed = kNoSlot;
  uint8_t trial = kNoSlot;
  TrialState trial_state = TrialState::kNone;
  uint32_t rollback_floor = 0;  ///< images with a lower counter are refused
};

/// Reads and appends boot-state records.
class BootStore {
 public:
  static constexpr uint32_t kRecordSize = 32;  ///< one program unit per record

  BootStore(hal::Flash* flash, const FlashLayout& layout) : flash_(flash), layout_(layout) {}

  /// The newest valid record of either sector (a default state when there is none).
  BootState Load();
  /// The same without reading flash again once loaded: Save keeps it, and nothing else writes
  /// the state while an image runs (a Hello asks for the rollback floor; a scan of both sectors
  /// is 512 record reads).
  BootState Newest() { return loaded_ ? newest_ : Load(); }
  /// Appends `state` with the next sequence number: into the sector holding the newest record
  /// while it has room, else into the other one after erasing it.
  protocol::Status Save(BootState state);

 private:
  bool ReadRecord(uint8_t sector, uint32_t index, BootState* state, bool* erased);
  hal::Flash* flash_;
  FlashLayout layout_;
  BootState newest_{};
  uint8_t newest_sector_ = 1;
  uint32_t newest_index_ = 0;
  bool loaded_ = false;
};

/// What is in a slot, as the bootloader sees it.
struct SlotImage {
  bool valid = false;  ///< header, TLVs, hash and trusted signature check, for this kind and slot
  protocol::ImageInfo info{};
  protocol::ImageError error = protocol::ImageError::kBadMagic;
};

/// Verifies the image in `slot` of `flash` (for `kind`), signed by one of the compiled-in
/// TrustedImageKeys(). Hashing a whole slot and checking its signature outlast a watchdog period
/// on a slow core, so `watchdog` (may be nullptr) is kicked for every block read and every step of
/// the signature check.
SlotImage InspectSlot(hal::Flash& flash, const FlashLayout& layout, uint8_t slot,
                      protocol::BoardKind kind, hal::Watchdog* watchdog = nullptr);

enum class BootReason : uint8_t {
  kConfirmed,  ///< the good image
  kTrial,      ///< a new image's one trial boot
  kReverted,   ///< the trial was reset before its confirmation: back to the good image
  kFallback,   ///< the expected image failed its check; the other slot's valid one instead
  kFirstBoot,  ///< no state yet: the valid image found
  kRecovery,   ///< no valid image: recovery mode (the bootstrap set over the link)
};
const char* BootReasonName(BootReason r);

struct BootDecision {
  uint8_t slot = kNoSlot;  ///< kNoSlot: recovery
  BootReason reason = BootReason::kRecovery;
  bool write_state = false;  ///< `next` must be saved before jumping
  BootState next{};
};

/// The bootloader's choice, pure: from the state and what the slots hold. A slot whose rollback
/// counter is below the floor counts as invalid.
BootDecision DecideBoot(const BootState& state, const SlotImage slots[2]);

/// Runs the choice against flash: loads the state, inspects both slots, saves the new state if
/// the choice needs it. The bootloader then jumps to `slot` (or enters recovery).
BootDecision Boot(hal::Flash& flash, const FlashLayout& layout, protocol::BoardKind kind,
                  SlotImage slots[2]);

}  // namespace palpa::core
