// Exclusive use of a serial port between processes: the lock-file convention of the FHS (a file
// /run/lock/LCK..NAME holding its owner's PID, which minicom, screen and ModemManager honour too),
// plus the kernel's TIOCEXCL on the open port, and the holder named when another process has it.
#pragma once

#include <string>

#include "palpa/host/transport.h"

namespace palpa::host {

class SerialLock {
 public:
  /// Takes the lock for the port at `path` (named after its real path: a symlink to /dev/pts/3
  /// locks "LCK..pts_3"). A lock whose owner is gone is taken over. When another process holds
  /// it, returns kBusy with *holder naming it ("pid 1234: palpa monitor"). A lock directory this
  /// user cannot write leaves the exclusion to TIOCEXCL alone (kOk, nothing locked).
  Status Acquire(const std::string& path, std::string* holder);
  /// Removes the lock file if this process still owns it.
  ~SerialLock();
  SerialLock() = default;
  SerialLock(const SerialLock&) = delete;
  SerialLock& operator=(const SerialLock&) = delete;

  /// The lock directory: $PALPA_LOCK_DIR, else /run/lock (the FHS's /var/lock).
  static std::string Directory();

 private:
  std::string file_;  ///< empty: nothing held
};

/// Who has `path` open, as the OS tells it (/proc/PID/fd): "pid 1234: palpa monitor", or empty.
std::string SerialHolder(const std::string& path);

/// Makes `fd` (a serial port) exclusive: a later open by anyone but root fails with EBUSY.
bool MakeExclusive(int fd);

}  // namespace palpa::host
