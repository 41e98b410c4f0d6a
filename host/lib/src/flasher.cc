// The host's side of a firmware update: the package checked against the board, then after the
// transfer (flash_transfer.cc) the image verified, activated, booted and confirmed.
#include "palpa/host/flasher.h"

#include <algorithm>
#include <chrono>
#include <initializer_list>
#include <thread>

#include "flash_update.h"
#include "palpa/host/signing_key.h"

namespace palpa::host {
namespace flash_internal {

double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string Why(const CommandResult& r) {
  std::string s = pp::StatusName(r.status);
  if (r.detail != 0) s += " (detail " + std::to_string(r.detail) + ")";
  if (!r.message.empty()) s += ": " + r.message;
  return s;
}

/// The package against the board: a valid image signed by the key it names (whether the board
/// trusts that key, the board says at activation), for this board's kind, not older than the
/// anti-rollback floor, not jumping past it, not a downgrade at an equal counter.
bool Update::Check() {
  pp::ImageInfo info;
  pp::ImageError error;
  if (VerifyImageBytes(image_, &info, &error) != Status::kOk) {
    std::string why = pp::ImageErrorName(error);
    if (error == pp::ImageError::kBadSignature)
      why += std::string(" (") + pp::SignatureCheckName(info.signature) + ")";
    return Fail(Status::kImageInvalid, std::string("the package's slot ") + std::to_string(slot_) +
                                           " image is invalid: " + why);
  }
  report_.signer_key_id = KeyId(info.signer);
  report_.to_version = VersionText(info.version_major, info.version_minor, info.version_revision);
  report_.package_counter = info.rollback_counter;
  if (info.board_kind != board_.board_kind) {
    return Fail(Status::kImageInvalid,
                std::string("the package is for a ") +
                    pp::EnumNames(pp::BoardKind{})[static_cast<size_t>(info.board_kind)] +
                    " board; this board is " +
                    pp::EnumNames(pp::BoardKind{})[static_cast<size_t>(board_.board_kind)]);
  }
  // The floor as of now: Hello's, raised by whatever the board has confirmed since.
  uint32_t floor = board_.rollback_counter;
  pp::SlotsReport slots{};
  const CommandResult q = link_.Command(pp::SlotsQuery{});
  if (q.status == Status::kOk && q.Reply(slots)) {
    for (uint8_t k = 0; k < slots.slot_count; ++k) {
      if (slots.slots[k].state == pp::SlotState::kConfirmed)
        floor = std::max(floor, slots.slots[k].rollback_counter);
    }
  }
  report_.board_floor = floor;
  if (info.rollback_counter < floor) {
    return Fail(Status::kRollbackRefused, "refused: the package's anti-rollback counter " +
                                              std::to_string(info.rollback_counter) +
                                              " is below the board's " + std::to_string(floor) +
                                              " (an older release)");
  }
  if (info.rollback_counter > floor + 1ull && !o_.allow_counter_jump) {
    return Fail(Status::kRollbackRefused,
                "refused: the package's anti-rollback counter " +
                    std::to_string(info.rollback_counter) + " jumps from the board's " +
                    std::to_string(floor) + "; once confirmed, no release below " +
                    std::to_string(info.rollback_counter) +
                    " can ever be installed on this board. Nothing was written; if the jump is "
                    "meant, flash with --allow-counter-jump");
  }
  const auto version = [](unsigned major, unsigned minor, unsigned patch) {
    return uint64_t{major} << 32 | uint64_t{minor} << 16 | patch;
  };
  if (info.rollback_counter == floor && !o_.allow_downgrade &&
      version(info.version_major, info.version_minor, info.version_revision) <
          version(board_.firmware_major, board_.firmware_minor, board_.firmware_patch)) {
    return Fail(Status::kRollbackRefused,
                "refused: " + report_.to_version + " is older than the running " +
                    report_.from_version + " at the same anti-rollback counter " +
                    std::to_string(floor) +
                    ". Nothing was written; to downgrade, flash with --allow-downgrade");
  }
  return true;
}

/// --dry-run: what would happen, nothing written.
bool Update::DryRun() {
  report_.message = "would write " + report_.to_version + " (" + std::to_string(image_.size()) +
                    " bytes) to slot " + std::to_string(slot_) + ", replacing " +
                    report_.from_version;
  return true;
}

/// 3. Verify what the board holds, then activate it for one trial boot.
bool Update::VerifyAndActivate() {
  pp::UpdateStatus st{};
  CommandResult r = link_.Command(pp::UpdateQuery{slot_});
  const pp::Sha256Digest digest = pp::Sha256Of(image_.data(), image_.size());
  if (r.status != Status::kOk || !r.Reply(st)) return Fail(r.status, "verify: " + Why(r));
  if (st.written_bytes != size_ || st.written_sha256 != digest) {
    return Fail(Status::kImageInvalid,
                "verify: the board holds " + std::to_string(st.written_bytes) +
                    " bytes whose SHA-256 is not the image's; nothing was activated");
  }
  Progress("verify", 1, 1, report_.write_seconds);
  r = link_.Command(pp::UpdateActivate{slot_, size_, digest});
  if (r.status == Status::kImageInvalid && r.detail > 0 &&
      r.detail <= static_cast<uint32_t>(pp::ImageError::kBadSignature)) {
    return Fail(r.status, std::string("activate: the board refused the image: ") +
                              pp::ImageErrorName(static_cast<pp::ImageError>(r.detail)) +
                              "; nothing was activated");
  }
  if (r.status != Status::kOk) return Fail(r.status, "activate: " + Why(r));
  Progress("activate", 1, 1, report_.write_seconds);
  return true;
}

/// 4. Reboot into the trial, and see the new image answer Hello over this link.
bool Update::Reboot() {
  const uint32_t nonce = board_.boot_nonce;
  if (o_.before_reboot) o_.before_reboot();
  const CommandResult r = link_.Command(pp::UpdateReboot{});
  if (r.status != Status::kOk) return Fail(r.status, "reboot: " + Why(r));
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(o_.reboot_timeout_ms);
  while (!(link_.session_open() && link_.board().boot_nonce != nonce)) {
    if (std::chrono::steady_clock::now() > deadline) {
      return Fail(Status::kTimeout,
                  "the board did not answer after the reboot; unconfirmed, it returns to " +
                      report_.from_version + " on its next reset");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const pp::HelloReply after = link_.board();
  Progress("reboot", 1, 1, report_.write_seconds);
  const std::string running =
      VersionText(after.firmware_major, after.firmware_minor, after.firmware_patch);
  if (after.active_slot != slot_ || running != report_.to_version) {
    return Fail(Status::kImageInvalid, "the board came back on " + running + " (slot " +
                                           std::to_string(after.active_slot) + "), not " +
                                           report_.to_version + ": it did not take the new image");
  }
  return true;
}

/// 5. Confirm: from now on the new image is the good one.
bool Update::Confirm() {
  const CommandResult r = link_.Command(pp::UpdateConfirm{slot_});
  if (r.status != Status::kOk) {
    return Fail(r.status, "confirm: " + Why(r) + "; unconfirmed, the board returns to " +
                              report_.from_version + " on its next reset");
  }
  Progress("confirm", 1, 1, report_.write_seconds);
  report_.message = "updated " + report_.from_version + " → " + report_.to_version + " (slot " +
                    std::to_string(slot_) + "), confirmed";
  return true;
}

}  // namespace flash_internal

std::string VersionText(uint8_t major, uint8_t minor, unsigned patch) {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

FlashReport FlashPackage(Link& link, const UpdatePackage& package, const FlashOptions& o) {
  using flash_internal::Update;
  Update update(link, package, o);
  if (!update.Check()) return update.report();
  if (o.dry_run) {
    update.DryRun();
    return update.report();
  }
  for (bool (Update::*phase)() : {&Update::Enter, &Update::Write, &Update::VerifyAndActivate,
                                  &Update::Reboot, &Update::Confirm}) {
    if (!(update.*phase)()) break;
  }
  return update.report();
}

}  // namespace palpa::host
