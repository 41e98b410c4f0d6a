// Flashing a board over the link it is controlled with: the package checked against the board
// (signature, kind, anti-rollback counter and its jump, version), the image for the inactive slot
// erased and written (resumable from what the board reports written, with its hash), activated for
// one trial boot, the board rebooted and seen to answer Hello on the new image, then confirmed.
#pragma once

#include <functional>
#include <string>

#include "palpa/host/firmware_image.h"
#include "palpa/host/link.h"
#include "palpa/host/outcome.h"

namespace palpa::host {

struct FlashProgress {
  std::string step;              ///< "erase", "write", "verify", "activate", "reboot", "confirm"
  uint32_t done = 0, total = 0;  ///< bytes (write) or 0/1
  double seconds = 0;            ///< since the write began
};

struct FlashOptions {
  bool resume = false;   ///< go on from what the board reports written (when its hash agrees)
  bool dry_run = false;  ///< check and report the version change; write nothing
  /// A lower version than the running one at the same anti-rollback counter is refused unless
  /// allowed (at a lower counter the board refuses it in any case).
  bool allow_downgrade = false;
  /// A counter more than one above the board's floor is refused unless allowed: once confirmed,
  /// nothing below it can ever be installed again.
  bool allow_counter_jump = false;
  int erase_timeout_ms = 60000;
  int reboot_timeout_ms = 15000;
  /// Called just before the reboot into the new image (release a held boot pin here).
  std::function<void()> before_reboot;
  std::function<void(const FlashProgress&)> progress;
};

/// The update's Outcome (status, and what happened or why not in words) and what it did.
struct FlashReport : Outcome {
  std::string from_version, to_version;
  std::string signer_key_id;  ///< KeyId of the key the package's image names (and is signed by)
  uint32_t board_floor = 0, package_counter = 0;
  uint8_t slot = 0;            ///< the slot written
  uint32_t bytes_written = 0;  ///< this run (less than the image when resumed)
  uint32_t resumed_from = 0;
  /// The session ended mid-write (the host stalled past the board's host-silence timeout, or
  /// the board reset) and the write went on from what the board reported, this many times.
  int resumed_after_session_loss = 0;
  double write_seconds = 0;
};

/// "1.2.3".
std::string VersionText(uint8_t major, uint8_t minor, unsigned patch);

/// Runs the update on an open link (its session reconnects across the reboot, and across a session
/// the board ended mid-write: the write resumes from what the board reports, a few times at most).
FlashReport FlashPackage(Link& link, const UpdatePackage& package, const FlashOptions& options);

}  // namespace palpa::host
