// Boot-state records and the bootloader's choice of slot.
#include "palpa/core/boot_state.h"

#include "palpa/core/trusted_keys.h"
#include "palpa/protocol/little_endian.h"

#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

using protocol::Status;

constexpr uint32_t kRecordMagic = 0x54534250;  // "PBST"

/// A slot of flash read as an image; the watchdog is kicked for every block the hash reads and
/// every step of the signature check.
class SlotSource final : public protocol::ImageSource, public protocol::VerifyProgress {
 public:
  SlotSource(hal::Flash& flash, uint32_t base, hal::Watchdog* watchdog)
      : flash_(flash), base_(base), watchdog_(watchdog) {}
  bool Read(uint32_t offset, uint8_t* out, size_t size) override {
    if (watchdog_ != nullptr) watchdog_->Kick();  // the hash reads a block at a time
    return flash_.Read(base_ + offset, out, size) == Status::kOk;
  }
  void Step() override {
    if (watchdog_ != nullptr) watchdog_->Kick();
  }

 private:
  hal::Flash& flash_;
  uint32_t base_;
  hal::Watchdog* watchdog_;
};

bool Bootable(const SlotImage& s, uint32_t floor) {
  return s.valid && s.info.rollback_counter >= floor;
}

}  // namespace

bool BootStore::ReadRecord(uint8_t sector, uint32_t index, BootState* state, bool* erased) {
  uint8_t r[kRecordSize];
  *erased = false;
  if (flash_->Read(layout_.state_offset[sector] + index * kRecordSize, r, sizeof(r)) != Status::kOk)
    return false;
  bool all_ones = true;
  for (uint8_t b : r) all_ones = all_ones && b == 0xFF;
  *erased = all_ones;
  if (all_ones || protocol::LoadLe32(r) != kRecordMagic ||
      protocol::LoadLe32(r + 28) != protocol::Crc32(r, 28))
    return false;
  if (r[8] > 1 && r[8] != kNoSlot) return false;
  if (r[9] > 1 && r[9] != kNoSlot) return false;
  if (r[10] > static_cast<uint8_t>(TrialState::kBooting)) return false;
  state->sequence = protocol::LoadLe32(r + 4);
  state->confirmed = r[8];
  state->trial = r[9];
  state->trial_state = static_cast<TrialState>(r[10]);
  state->rollback_floor = protocol::LoadLe32(r + 12);
  return true;
}

BootState BootStore::Load() {
  newest_ = BootState{};
  newest_sector_ = 1;  // no record: the first save erases and uses sector 0
  newest_index_ = layout_.sector_size / kRecordSize;
  const uint32_t records = layout_.sector_size / kRecordSize;
  for (uint8_t sector = 0; sector < 2; ++sector) {
    for (uint32_t i = 0; i < records; ++i) {
      BootState s;
      bool erased = false;
      if (ReadRecord(sector, i, &s, &erased) && s.sequence > newest_.sequence) {
        newest_ = s;
        newest_sector_ = sector;
        newest_index_ = i;
      }
    }
  }
  loaded_ = true;
  return newest_;
}

Status BootStore::Save(BootState state) {
  if (flash_ == nullptr) return Status::kUnavailable;
  if (!loaded_) Load();
  state.sequence = newest_.sequence + 1;
  uint8_t r[kRecordSize];
  for (uint8_t& b : r) b = 0;
  protocol::StoreLe32(r, kRecordMagic);
  protocol::StoreLe32(r + 4, state.sequence);
  r[8] = state.confirmed;
  r[9] = state.trial;
  r[10] = static_cast<uint8_t>(state.trial_state);
  protocol::StoreLe32(r + 12, state.rollback_floor);
  protocol::StoreLe32(r + 28, protocol::Crc32(r, 28));
  // The first erased record after the newest one in its sector (a torn one is skipped).
  const uint32_t records = layout_.sector_size / kRecordSize;
  uint8_t sector = newest_sector_;
  uint32_t index = records;
  for (uint32_t i = newest_index_ + 1; i < records; ++i) {
    BootState ignored;
    bool erased = false;
    ReadRecord(sector, i, &ignored, &erased);
    if (erased) {
      index = i;
      break;
    }
  }
  if (index == records) {  // full: the other sector, erased first (it holds only older records)
    sector = static_cast<uint8_t>(1 - sector);
    index = 0;
    const Status e = flash_->Erase(layout_.state_offset[sector]);
    if (e != Status::kOk) return e;
  }
  const Status p =
      flash_->Program(layout_.state_offset[sector] + index * kRecordSize, r, sizeof(r));
  if (p != Status::kOk) return p;
  BootState back;
  bool erased = false;
  if (!ReadRecord(sector, index, &back, &erased) || back.sequence != state.sequence)
    return Status::kIoError;  // read back: a record that does not verify never counts
  newest_ = state;
  newest_sector_ = sector;
  newest_index_ = index;
  return Status::kOk;
}

SlotImage InspectSlot(hal::Flash& flash, const FlashLayout& layout, uint8_t slot,
                      protocol::BoardKind kind, hal::Watchdog* watchdog) {
  SlotImage s;
  SlotSource source(flash, layout.slot_offset[slot], watchdog);
  s.valid = protocol::VerifyImage(source, layout.slot_size, &TrustedImageKeys(), &s.info, &s.error,
                                  &source) == Status::kOk;
  if (s.valid && (s.info.board_kind != kind || s.info.slot != slot ||
                  s.info.load_address != layout.xip_base + layout.slot_offset[slot])) {
    s.valid = false;  // a good image, but not for this board or not linked for this slot
    s.error = protocol::ImageError::kBadHeader;
  }
  return s;
}

const char* BootReasonName(BootReason r) {
  switch (r) {
    case BootReason::kConfirmed:
      return "confirmed image";
    case BootReason::kTrial:
      return "trial boot of the new image";
    case BootReason::kReverted:
      return "reverted: the trial was not confirmed";
    case BootReason::kFallback:
      return "fallback: the expected image failed its check";
    case BootReason::kFirstBoot:
      return "first boot";
    case BootReason::kRecovery:
      return "recovery mode: no valid image";
  }
  return "?";
}

BootDecision DecideBoot(const BootState& state, const SlotImage slots[2]) {
  BootDecision d;
  d.next = state;
  const uint32_t floor = state.rollback_floor;
  auto ok = [&](uint8_t slot) { return slot <= 1 && Bootable(slots[slot], floor); };
  auto choose = [&](uint8_t slot, BootReason reason) {
    d.slot = slot;
    d.reason = reason;
    return d;
  };
  if (state.trial_state == TrialState::kBooting) {
    // The trial image ran and the board reset before the host confirmed it: revert.
    d.write_state = true;
    d.next.trial = kNoSlot;
    d.next.trial_state = TrialState::kNone;
    if (ok(state.confirmed)) return choose(state.confirmed, BootReason::kReverted);
  } else if (state.trial_state == TrialState::kPending && ok(state.trial)) {
    d.write_state = true;  // marked before the jump: a reset from here on reverts
    d.next.trial_state = TrialState::kBooting;
    return choose(state.trial, BootReason::kTrial);
  } else if (state.trial_state == TrialState::kPending) {
    d.write_state = true;  // the activated image no longer checks: forget it
    d.next.trial = kNoSlot;
    d.next.trial_state = TrialState::kNone;
  }
  if (ok(state.confirmed)) return choose(state.confirmed, BootReason::kConfirmed);
  // No good image where the state says: any valid one, and it becomes the confirmed one (the
  // first boot of a factory-programmed board, or the good slot lost).
  for (uint8_t slot = 0; slot < 2; ++slot) {
    if (!ok(slot)) continue;
    d.write_state = true;
    d.next.confirmed = slot;
    d.next.trial = kNoSlot;
    d.next.trial_state = TrialState::kNone;
    // The floor stays: it moves only when the host confirms an image it activated.
    return choose(slot, state.sequence == 0 ? BootReason::kFirstBoot : BootReason::kFallback);
  }
  d.write_state = false;
  return choose(kNoSlot, BootReason::kRecovery);
}

BootDecision Boot(hal::Flash& flash, const FlashLayout& layout, protocol::BoardKind kind,
                  SlotImage slots[2]) {
  BootStore store(&flash, layout);
  const BootState state = store.Load();
  for (uint8_t slot = 0; slot < 2; ++slot) slots[slot] = InspectSlot(flash, layout, slot, kind);
  BootDecision d = DecideBoot(state, slots);
  if (d.write_state && store.Save(d.next) != protocol::Status::kOk &&
      d.reason == BootReason::kTrial) {
    // The trial could not be recorded: booting it anyway would lose the way back. Stay put.
    BootState unchanged = state;
    unchanged.trial_state = TrialState::kNone;
    d = DecideBoot(unchanged, slots);
    d.write_state = false;
  }
  return d;
}

}  // namespace palpa::core
