// The host's side of a firmware update.
#include "palpa/host/flasher.h"

#include <algorithm>
#include <chrono>
#include <deque>
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

FlashReport Fail(FlashReport report, Status status, std::string message) {
  report.status = status;
  report.message = std::move(message);
  return report;
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

FlashReport FlashPackage(Link& link, const UpdatePackage& package, const FlashOptions& o) {
  FlashReport report;
  const pp::HelloReply board = link.board();
  report.from_version =
      VersionText(board.firmware_major, board.firmware_minor, board.firmware_patch);
  // The board names its running slot; the other one is written (in recovery mode, the one it
  // reports inactive all the same).
  const uint8_t slot = static_cast<uint8_t>(1 - board.active_slot);
  report.slot = slot;
  const std::vector<uint8_t>& image = package.slot_image[slot];
  pp::ImageInfo info;
  pp::ImageError error;
  if (VerifyImageBytes(image, &info, &error) != Status::kOk) {
    return Fail(report, Status::kImageInvalid,
                std::string("the package's slot ") + std::to_string(slot) +
                    " image is invalid: " + pp::ImageErrorName(error));
  }
  report.to_version = VersionText(info.version_major, info.version_minor, info.version_revision);
  if (info.board_kind != board.board_kind) {
    return Fail(report, Status::kImageInvalid,
                std::string("the package is for a ") +
                    pp::EnumNames(pp::BoardKind{})[static_cast<size_t>(info.board_kind)] +
                    " board; this board is " +
                    pp::EnumNames(pp::BoardKind{})[static_cast<size_t>(board.board_kind)]);
  }
  // The floor as of now: Hello's, raised by whatever the board has confirmed since.
  uint32_t floor = board.rollback_counter;
  pp::SlotsReport slots{};
  const CommandResult q = link.Command(pp::SlotsQuery{});
  if (q.status == Status::kOk && q.Reply(slots)) {
    for (uint8_t k = 0; k < slots.slot_count; ++k) {
      if (slots.slots[k].state == pp::SlotState::kConfirmed)
        floor = std::max(floor, slots.slots[k].rollback_counter);
    }
  }
  if (info.rollback_counter < floor) {
    return Fail(report, Status::kRollbackRefused,
                "refused: the package's anti-rollback counter " +
                    std::to_string(info.rollback_counter) + " is below the board's " +
                    std::to_string(floor) + " (an older release)");
  }
  if (o.dry_run) {
    report.message = "would write " + report.to_version + " (" + std::to_string(image.size()) +
                     " bytes) to slot " + std::to_string(slot) + ", replacing " +
                     report.from_version;
    return report;
  }
  auto progress = [&](const char* step, uint32_t done, uint32_t total, double seconds) {
    if (o.progress) o.progress(FlashProgress{step, done, total, seconds});
  };
  const auto size = static_cast<uint32_t>(image.size());

  // 1. Update mode (the board's lines go safe), and where to start.
  CommandResult r = link.Command(pp::UpdateEnter{slot, size});
  if (r.status != Status::kOk) return Fail(report, r.status, "enter update mode: " + Why(r));
  uint32_t start = 0;
  if (o.resume) {
    pp::UpdateStatus st{};
    r = link.Command(pp::UpdateQuery{slot});
    if (r.status == Status::kOk && r.Reply(st) && st.written_bytes <= size &&
        st.written_sha256 == pp::Sha256Of(image.data(), st.written_bytes)) {
      start = st.written_bytes;  // what is there is this image's beginning: go on from it
    }
  }
  report.resumed_from = start;
  if (start == 0) {
    progress("erase", 0, 1, 0);
    r = link.Command(pp::UpdateErase{slot, 0, size}, o.erase_timeout_ms);
    if (r.status != Status::kOk) return Fail(report, r.status, "erase: " + Why(r));
    progress("erase", 1, 1, 0);
  }

  // 2. Write, contiguously, several chunks in the link's window at once (they arrive in order);
  //    a Nack at the wrong offset names the resume point.
  constexpr size_t kInFlight = 4;
  struct Flight {
    uint32_t ticket, at, size;
  };
  std::deque<Flight> flight;
  auto drain = [&] {
    for (const Flight& f : flight) link.Await(f.ticket);
    flight.clear();
  };
  const auto began = std::chrono::steady_clock::now();
  for (uint32_t next = start; next < size || !flight.empty();) {
    while (next < size && flight.size() < kInFlight) {
      pp::UpdateWrite w;
      w.slot = slot;
      w.offset = next;
      w.data_size = static_cast<uint8_t>(std::min<uint32_t>(pp::kMaxUpdateChunk, size - next));
      std::copy(image.begin() + next, image.begin() + next + w.data_size, w.data.begin());
      flight.push_back({link.Submit(w), next, w.data_size});
      next += w.data_size;
    }
    const Flight f = flight.front();
    flight.pop_front();
    r = link.Await(f.ticket);
    if (r.status == Status::kOutOfRange && r.detail < f.at) {
      drain();  // the board has less than we thought (it reset): from there
      next = r.detail;
      continue;
    }
    if (SessionLost(r.status) && report.resumed_after_session_loss < kMaxResumes) {
      drain();  // what the board holds decides where to go on
      if (const auto point = ResumePoint(link, slot, image, o)) {
        ++report.resumed_after_session_loss;
        next = *point;
        continue;
      }
    }
    if (r.status != Status::kOk) {
      drain();
      report.write_seconds = Since(began);
      return Fail(report, r.status,
                  "write at " + std::to_string(f.at) + " of " + std::to_string(size) + ": " +
                      Why(r) + "; run again with --resume to go on from what the board has");
    }
    report.bytes_written += f.size;
    progress("write", f.at + f.size, size, Since(began));
  }
  report.write_seconds = Since(began);

  // 3. Verify what the board holds, then activate it for one trial boot.
  pp::UpdateStatus st{};
  r = link.Command(pp::UpdateQuery{slot});
  const pp::Sha256Digest digest = pp::Sha256Of(image.data(), image.size());
  if (r.status != Status::kOk || !r.Reply(st)) return Fail(report, r.status, "verify: " + Why(r));
  if (st.written_bytes != size || st.written_sha256 != digest) {
    return Fail(report, Status::kImageInvalid,
                "verify: the board holds " + std::to_string(st.written_bytes) +
                    " bytes whose SHA-256 is not the image's; nothing was activated");
  }
  progress("verify", 1, 1, report.write_seconds);
  r = link.Command(pp::UpdateActivate{slot, size, digest});
  if (r.status != Status::kOk) return Fail(report, r.status, "activate: " + Why(r));
  progress("activate", 1, 1, report.write_seconds);

  // 4. Reboot into the trial, and see the new image answer Hello over this link.
  const uint32_t nonce = board.boot_nonce;
  if (o.before_reboot) o.before_reboot();
  r = link.Command(pp::UpdateReboot{});
  if (r.status != Status::kOk) return Fail(report, r.status, "reboot: " + Why(r));
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(o.reboot_timeout_ms);
  while (!(link.session_open() && link.board().boot_nonce != nonce)) {
    if (std::chrono::steady_clock::now() > deadline) {
      return Fail(report, Status::kTimeout,
                  "the board did not answer after the reboot; unconfirmed, it returns to " +
                      report.from_version + " on its next reset");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const pp::HelloReply after = link.board();
  progress("reboot", 1, 1, report.write_seconds);
  const std::string running =
      VersionText(after.firmware_major, after.firmware_minor, after.firmware_patch);
  if (after.active_slot != slot || running != report.to_version) {
    return Fail(report, Status::kImageInvalid,
                "the board came back on " + running + " (slot " +
                    std::to_string(after.active_slot) + "), not " + report.to_version +
                    ": it did not take the new image");
  }

  // 5. Confirm: from now on the new image is the good one.
  r = link.Command(pp::UpdateConfirm{slot});
  if (r.status != Status::kOk) {
    return Fail(report, r.status,
                "confirm: " + Why(r) + "; unconfirmed, the board returns to " +
                    report.from_version + " on its next reset");
  }
  progress("confirm", 1, 1, report.write_seconds);
  report.message = "updated " + report.from_version + " → " + report.to_version + " (slot " +
                   std::to_string(slot) + "), confirmed";
  return report;
}

}  // namespace palpa::host
