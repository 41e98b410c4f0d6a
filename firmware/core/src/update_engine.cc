// Update engine: inactive-slot erase and contiguous writes with a running hash, activation after
// a full check, confirmation of the running trial image.
#include "palpa/core/update_engine.h"

namespace palpa::core {
namespace {

using protocol::Status;

}  // namespace

UpdateEngine::UpdateEngine(hal::Flash* flash, const FlashLayout& layout, protocol::BoardKind kind,
                           uint8_t running, hal::Watchdog* watchdog)
    : flash_(flash),
      watchdog_(watchdog),
      layout_(layout),
      kind_(kind),
      running_(running),
      store_(flash, layout) {
  if (running <= 1) {
    inactive_ = static_cast<uint8_t>(1 - running);
  } else {  // recovery: anything but the slot the state still calls good (if any)
    const BootState s = flash != nullptr ? store_.Load() : BootState{};
    inactive_ = s.confirmed == 0 ? 1 : 0;
  }
}

Status UpdateEngine::Writable(uint8_t slot) const {
  if (flash_ == nullptr) return Status::kUnavailable;
  if (!update_mode_) return Status::kWrongMode;
  if (slot != inactive_) return Status::kOutOfRange;  // never the running image
  return Status::kOk;
}

Status UpdateEngine::Enter(const protocol::UpdateEnter& m, uint32_t* detail) {
  *detail = 0;
  if (flash_ == nullptr) return Status::kUnavailable;
  if (m.slot != inactive_) {
    *detail = inactive_;
    return Status::kOutOfRange;
  }
  if (m.image_size == 0 || m.image_size > layout_.slot_size) {
    *detail = layout_.slot_size;
    return Status::kOutOfRange;
  }
  if (m.image_size != image_size_) {  // entering again with the same image size resumes
    written_ = 0;
    erased_ = 0;
    hash_.Reset();
  }
  update_mode_ = true;
  image_size_ = m.image_size;
  return Status::kOk;
}

Status UpdateEngine::Erase(const protocol::UpdateErase& m, uint32_t* detail) {
  *detail = 0;
  const Status w = Writable(m.slot);
  if (w != Status::kOk) return w;
  // The sectors covering [offset, offset + length): the host need not know the sector size.
  const uint32_t sector = layout_.sector_size;
  if (m.length == 0 || m.offset + m.length > layout_.slot_size || m.offset + m.length < m.offset) {
    *detail = layout_.slot_size;
    return Status::kOutOfRange;
  }
  const uint32_t first = m.offset / sector * sector;
  const uint32_t end = (m.offset + m.length + sector - 1) / sector * sector;
  for (uint32_t at = first; at < end; at += sector) {
    Kick();
    const Status e = flash_->Erase(layout_.slot_offset[m.slot] + at);
    if (e != Status::kOk) {
      *detail = at;
      return e;
    }
  }
  // Written bytes inside the erased range are gone; erased coverage grows when contiguous.
  if (first < written_) {
    written_ = 0;  // the hash covers from 0: start it again
    hash_.Reset();
  }
  if (first <= erased_ && end > erased_) erased_ = end;
  return Status::kOk;
}

Status UpdateEngine::Write(const protocol::UpdateWrite& m, uint32_t* detail) {
  *detail = written_;
  const Status w = Writable(m.slot);
  if (w != Status::kOk) return w;
  const uint32_t end = m.offset + m.data_size;
  if (m.data_size == 0 || end > image_size_ || end < m.offset) return Status::kOutOfRange;
  const uint32_t base = layout_.slot_offset[m.slot];
  if (end <= written_) {  // a chunk sent again (its Ack was lost): fine if it is what is there
    uint8_t stored[protocol::kMaxUpdateChunk];
    if (flash_->Read(base + m.offset, stored, m.data_size) != Status::kOk) return Status::kIoError;
    for (uint8_t i = 0; i < m.data_size; ++i) {
      if (stored[i] != m.data[i]) return Status::kOutOfRange;
    }
    return Status::kOk;
  }
  if (m.offset != written_) return Status::kOutOfRange;  // *detail: where to resume
  if (end > erased_) return Status::kUnavailable;        // erase first
  Kick();
  const Status p = flash_->Program(base + m.offset, m.data.data(), m.data_size);
  uint8_t back[protocol::kMaxUpdateChunk];
  if (p != Status::kOk || flash_->Read(base + m.offset, back, m.data_size) != Status::kOk)
    return Status::kIoError;
  for (uint8_t i = 0; i < m.data_size; ++i) {
    if (back[i] != m.data[i]) return Status::kIoError;  // a bad cell: the host erases again
  }
  hash_.Update(m.data.data(), m.data_size);
  written_ = end;
  *detail = written_;
  return Status::kOk;
}

protocol::UpdateStatus UpdateEngine::Query(uint8_t slot) const {
  protocol::UpdateStatus s;
  s.slot = slot;
  s.in_update_mode = update_mode_;
  if (slot == inactive_) {
    s.written_bytes = written_;
    protocol::Sha256Hasher copy = hash_;
    s.written_sha256 = copy.Finish();
  }
  return s;
}

Status UpdateEngine::Activate(const protocol::UpdateActivate& m, uint32_t* detail) {
  *detail = 0;
  const Status w = Writable(m.slot);
  if (w != Status::kOk) return w;
  if (written_ != m.image_size || m.image_size != image_size_) {
    *detail = written_;
    return Status::kUnavailable;  // not all written
  }
  const SlotImage image = InspectSlot(*flash_, layout_, m.slot, kind_, watchdog_);
  if (!image.valid || image.info.total_size != m.image_size) {
    *detail = static_cast<uint32_t>(image.error);
    return Status::kImageInvalid;
  }
  protocol::Sha256Hasher copy = hash_;
  if (copy.Finish() != m.image_sha256) return Status::kImageInvalid;  // not the host's image
  BootState state = store_.Load();
  if (image.info.rollback_counter < state.rollback_floor) {
    *detail = state.rollback_floor;
    return Status::kRollbackRefused;
  }
  state.trial = m.slot;
  state.trial_state = TrialState::kPending;
  return store_.Save(state);
}

Status UpdateEngine::Confirm(const protocol::UpdateConfirm& m, uint32_t* detail) {
  *detail = 0;
  if (flash_ == nullptr) return Status::kUnavailable;
  BootState state = store_.Load();
  if (m.slot != running_) return Status::kOutOfRange;
  if (state.confirmed == running_ && state.trial_state == TrialState::kNone)
    return Status::kOk;  // already the good image (a repeated confirm)
  if (state.trial != running_ || state.trial_state != TrialState::kBooting)
    return Status::kWrongMode;
  const SlotImage image = InspectSlot(*flash_, layout_, running_, kind_, watchdog_);
  if (!image.valid) return Status::kImageInvalid;
  state.confirmed = running_;
  state.trial = kNoSlot;
  state.trial_state = TrialState::kNone;
  if (image.info.rollback_counter > state.rollback_floor)
    state.rollback_floor = image.info.rollback_counter;
  return store_.Save(state);
}

protocol::SlotsReport UpdateEngine::Slots() {
  protocol::SlotsReport r;
  const BootState state = flash_ != nullptr ? store_.Load() : BootState{};
  r.active_slot = running_ <= 1 ? running_ : 0;
  r.slot_count = 2;
  for (uint8_t slot = 0; slot < 2; ++slot) {
    protocol::SlotInfo& info = r.slots[slot];
    if (flash_ == nullptr) continue;
    const SlotImage image = InspectSlot(*flash_, layout_, slot, kind_, watchdog_);
    if (!image.valid) {
      info.state = image.error == protocol::ImageError::kBadMagic ? protocol::SlotState::kEmpty
                                                                  : protocol::SlotState::kInvalid;
      continue;
    }
    info.board_kind = image.info.board_kind;
    info.version_major = image.info.version_major;
    info.version_minor = image.info.version_minor;
    info.version_patch = static_cast<uint8_t>(image.info.version_revision);
    info.rollback_counter = image.info.rollback_counter;
    info.image_size = image.info.total_size;
    info.state = state.confirmed == slot ? protocol::SlotState::kConfirmed
                 : state.trial == slot && state.trial_state != TrialState::kNone
                     ? protocol::SlotState::kTrial
                     : protocol::SlotState::kValid;
  }
  return r;
}

}  // namespace palpa::core
