// One firmware update's phases and what they share, for the two halves of the flasher: the
// image's transfer (flash_transfer.cc) and the checks and switch-over around it (flasher.cc).
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "palpa/host/flasher.h"

namespace palpa::host::flash_internal {

/// Seconds since `t`.
double Since(std::chrono::steady_clock::time_point t);
/// A refused command in words: its status, detail and message.
std::string Why(const CommandResult& r);

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

}  // namespace palpa::host::flash_internal
