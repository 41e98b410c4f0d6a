// The host's side of a firmware update.
#include "palpa/host/flasher.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <initializer_list>
#include <optional>
#include <thread>

namespace palpa::host {
namespace {

double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string Why(const CommandResult& r) {
  std::string s = pp::StatusName(r.status);
  if (r.detail != 0) s += " (detail " + std::to_string(r.detail) + ")";
  if (!r.message.empty()) s += ": " + r.message;
  return s;
}

/// A command that did not complete because the session ended under it.
bool SessionLost(Status s) { return s == Status::kOutcomeUnknown || s == Status::kNoSession; }
constexpr int kMaxResumes = 3;

/// Where to go on writing after the session ended mid-write: once the link has a session again,
/// update mode anew and the board's written prefix if it is the image's (else from 0, erased
/// again). Empty when the board cannot be reached or refuses.
std::optional<uint32_t> ResumePoint(Link& link, uint8_t slot, const std::vector<uint8_t>& image,
                                    const FlashOptions& o) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!link.session_open()) {
    if (link.ended() || std::chrono::steady_clock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const auto size = static_cast<uint32_t>(image.size());
  if (link.Command(pp::UpdateEnter{slot, size}).status != Status::kOk) return std::nullopt;
  pp::UpdateStatus st{};
  const CommandResult q = link.Command(pp::UpdateQuery{slot});
  if (q.status == Status::kOk && q.Reply(st) && st.written_bytes <= size && st.written_bytes > 0 &&
      st.written_sha256 == pp::Sha256Of(image.data(), st.written_bytes)) {
    return st.written_bytes;
  }
  if (link.Command(pp::UpdateErase{slot, 0, size}, o.erase_timeout_ms).status != Status::kOk)
    return std::nullopt;
  return 0;
}

}  // namespace

std::string VersionText(uint8_t major, uint8_t minor, unsigned patch) {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

namespace {

/// One update: what its phases share. Each phase returns false with the report's status and
/// message saying why it stopped there.
class Update {
 public:
  Update(Link& link, const UpdatePackage& package, const FlashOptions& o)
      : link_(link),
        o_(o),
        board_(link.board()),
        // The board names its running slot; the other one is written (in recovery mode, the
        // one it reports inactive all the same).
        slot_(static_cast<uint8_t>(1 - board_.active_slot)),
        image_(package.slot_image[slot_]),
        size_(static_cast<uint32_t>(image_.size())) {
    report_.from_version =
        VersionText(board_.firmware_major, board_.firmware_minor, board_.firmware_patch);
    report_.slot = slot_;
  }

  bool Check();
  bool DryRun();
  bool Enter();
  bool Write();
  bool VerifyAndActivate();
  bool Reboot();
  bool Confirm();
  FlashReport& report() { return report_; }

 private:
  bool Fail(Status status, std::string message) {
    report_.status = status;
    report_.message = std::move(message);
    return false;
  }
  void Progress(const char* step, uint32_t done, uint32_t total, double seconds) {
    if (o_.progress) o_.progress(FlashProgress{step, done, total, seconds});
  }

  Link& link_;
  const FlashOptions& o_;
  const pp::HelloReply board_;
  const uint8_t slot_;
  const std::vector<uint8_t>& image_;
  const uint32_t size_;
  FlashReport report_;
  uint32_t start_ = 0;
};

/// The package against the board: a valid image for this board's kind, not older than the
/// anti-rollback floor.
bool Update::Check() {
  pp::ImageInfo info;
  pp::ImageError error;
  if (VerifyImageBytes(image_, &info, &error) != Status::kOk) {
    return Fail(Status::kImageInvalid, std::string("the package's slot ") + std::to_string(slot_) +
                                           " image is invalid: " + pp::ImageErrorName(error));
  }
  report_.to_version = VersionText(info.version_major, info.version_minor, info.version_revision);
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
  if (info.rollback_counter < floor) {
    return Fail(Status::kRollbackRefused, "refused: the package's anti-rollback counter " +
                                              std::to_string(info.rollback_counter) +
                                              " is below the board's " + std::to_string(floor) +
                                              " (an older release)");
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

/// 1. Update mode (the board's lines go safe), and where to start: from what the board holds of
///    this image when resuming, else from 0 on an erased slot.
bool Update::Enter() {
  CommandResult r = link_.Command(pp::UpdateEnter{slot_, size_});
  if (r.status != Status::kOk) return Fail(r.status, "enter update mode: " + Why(r));
  if (o_.resume) {
    pp::UpdateStatus st{};
    r = link_.Command(pp::UpdateQuery{slot_});
    if (r.status == Status::kOk && r.Reply(st) && st.written_bytes <= size_ &&
        st.written_sha256 == pp::Sha256Of(image_.data(), st.written_bytes)) {
      start_ = st.written_bytes;  // what is there is this image's beginning: go on from it
    }
  }
  report_.resumed_from = start_;
  if (start_ == 0) {
    Progress("erase", 0, 1, 0);
    r = link_.Command(pp::UpdateErase{slot_, 0, size_}, o_.erase_timeout_ms);
    if (r.status != Status::kOk) return Fail(r.status, "erase: " + Why(r));
    Progress("erase", 1, 1, 0);
  }
  return true;
}

/// 2. Write, contiguously, several chunks in the link's window at once (they arrive in order);
///    a Nack at the wrong offset names the resume point.
bool Update::Write() {
  constexpr size_t kInFlight = 4;
  struct Flight {
    uint32_t ticket, at, size;
  };
  std::deque<Flight> flight;
  auto drain = [&] {
    for (const Flight& f : flight) link_.Await(f.ticket);
    flight.clear();
  };
  const auto began = std::chrono::steady_clock::now();
  for (uint32_t next = start_; next < size_ || !flight.empty();) {
    while (next < size_ && flight.size() < kInFlight) {
      pp::UpdateWrite w;
      w.slot = slot_;
      w.offset = next;
      w.data_size = static_cast<uint8_t>(std::min<uint32_t>(pp::kMaxUpdateChunk, size_ - next));
      std::copy(image_.begin() + next, image_.begin() + next + w.data_size, w.data.begin());
      flight.push_back({link_.Submit(w), next, w.data_size});
      next += w.data_size;
    }
    const Flight f = flight.front();
    flight.pop_front();
    const CommandResult r = link_.Await(f.ticket);
    if (r.status == Status::kOutOfRange && r.detail < f.at) {
      drain();  // the board has less than we thought (it reset): from there
      next = r.detail;
      continue;
    }
    if (SessionLost(r.status) && report_.resumed_after_session_loss < kMaxResumes) {
      drain();  // what the board holds decides where to go on
      if (const auto point = ResumePoint(link_, slot_, image_, o_)) {
        ++report_.resumed_after_session_loss;
        next = *point;
        continue;
      }
    }
    if (r.status != Status::kOk) {
      drain();
      report_.write_seconds = Since(began);
      return Fail(r.status, "write at " + std::to_string(f.at) + " of " + std::to_string(size_) +
                                ": " + Why(r) +
                                "; run again with --resume to go on from what the board has");
    }
    report_.bytes_written += f.size;
    Progress("write", f.at + f.size, size_, Since(began));
  }
  report_.write_seconds = Since(began);
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

}  // namespace

FlashReport FlashPackage(Link& link, const UpdatePackage& package, const FlashOptions& o) {
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
