// What a hosted board drives alone, claimed by a lock file the kernel releases when its holder
// dies: a second program is refused before it touches anything, and kill -9 leaves nothing stale.
#pragma once

#include <string>

namespace palpa::hosted {

/// The directory for run-time files of program NAME, made if missing: /run/NAME; where /run is not
/// writable (an unprivileged user), $XDG_RUNTIME_DIR/NAME, else /tmp/NAME-UID; each only when
/// PrivateDirectory says so. A claim only excludes programs that chose the same directory.
std::string RunDirectory(const std::string& name);

/// PATH made if missing, then true only when it is a directory (not a link) of this user that no
/// one else may write into: a neighbour cannot plant a lock file there.
bool PrivateDirectory(const std::string& path);

/// KEY as a file name: every character but letters, digits, '.', '-' and '_' becomes '_'.
std::string LockFileName(const std::string& key);

class ProcessClaim {
 public:
  ProcessClaim() = default;
  ~ProcessClaim() { Release(); }
  ProcessClaim(const ProcessClaim&) = delete;
  ProcessClaim& operator=(const ProcessClaim&) = delete;

  /// Takes `lock_path` (made if missing, never followed through a link; flock, exclusive) for WHAT
  /// (a phrase for messages: "gadget palpa") and writes this process's id into it. False when a
  /// running process holds it, *error naming WHAT and that process.
  bool Take(const std::string& lock_path, const std::string& what, std::string* error);
  void Release();

 private:
  int fd_ = -1;
};

}  // namespace palpa::hosted
