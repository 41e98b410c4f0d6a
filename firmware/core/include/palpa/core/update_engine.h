// The board's side of a firmware update (the bootstrap set's update messages): erase and write
// the inactive slot, report how much is written and its hash (the resume point), verify and
// activate the new image for one trial boot, and confirm it once the host has seen it answer.
// The application and the bootloader's recovery mode both run it. Lines stay safe meanwhile:
// the board refuses every output command while update mode is on.
#pragma once

#include <cstdint>

#include "palpa/core/boot_state.h"
#include "palpa/hal/watchdog.h"
#include "palpa/protocol/messages_update.h"
#include "palpa/protocol/sha256.h"

namespace palpa::core {

class UpdateEngine {
 public:
  /// `running` is the slot executing now (kNoSlot in recovery mode: both slots are writable).
  /// `watchdog` (may be nullptr) is kicked between sectors of an erase, around every flash
  /// operation and for every block an image check hashes: long work, not a hung loop. The lines
  /// are safe throughout (update mode).
  UpdateEngine(hal::Flash* flash, const FlashLayout& layout, protocol::BoardKind kind,
               uint8_t running, hal::Watchdog* watchdog = nullptr);

  bool in_update_mode() const { return update_mode_; }
  /// A new session: an update its host abandoned no longer holds the board (lines safe, output
  /// commands refused) until a reset. What is written stays: an Enter with the same image size
  /// resumes it, as a host that lost its link does.
  void LeaveUpdateMode() { update_mode_ = false; }

  /// Each returns kOk, or why not; *detail carries an index or, for a write at the wrong offset,
  /// the resume point.
  protocol::Status Enter(const protocol::UpdateEnter& m, uint32_t* detail);
  protocol::Status Erase(const protocol::UpdateErase& m, uint32_t* detail);
  protocol::Status Write(const protocol::UpdateWrite& m, uint32_t* detail);
  protocol::UpdateStatus Query(uint8_t slot) const;
  protocol::Status Activate(const protocol::UpdateActivate& m, uint32_t* detail);
  protocol::Status Confirm(const protocol::UpdateConfirm& m, uint32_t* detail);
  protocol::SlotsReport Slots();

  /// The slot an update may write: the one not running (nor holding the confirmed image).
  uint8_t inactive_slot() const { return inactive_; }
  uint32_t rollback_floor() { return store_.Newest().rollback_floor; }

 private:
  protocol::Status Writable(uint8_t slot) const;
  void Kick() {
    if (watchdog_ != nullptr) watchdog_->Kick();
  }
  hal::Flash* flash_;
  hal::Watchdog* watchdog_;
  FlashLayout layout_;
  protocol::BoardKind kind_;
  uint8_t running_;
  uint8_t inactive_;
  BootStore store_;
  bool update_mode_ = false;
  uint32_t image_size_ = 0;
  uint32_t written_ = 0;         ///< contiguous from 0 since the erase
  uint32_t erased_ = 0;          ///< bytes from 0 known erased
  protocol::Sha256Hasher hash_;  ///< of the written bytes (a copy gives the running digest)
};

}  // namespace palpa::core
