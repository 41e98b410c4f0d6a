// The run directory and the lock a running program holds on what it drives.
#include "process_claim.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace palpa::hosted {
bool PrivateDirectory(const std::string& path) {
  mkdir(path.c_str(), 0755);  // EEXIST is fine; whose it is is asked next
  // A directory another user made (or made writable to others) would let that user plant the
  // lock file as a link to any file this program may write, or hold the claim: refused.
  struct stat st {};
  return lstat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == geteuid() &&
         (st.st_mode & (S_IWGRP | S_IWOTH)) == 0 && access(path.c_str(), W_OK | X_OK) == 0;
}

std::string RunDirectory(const std::string& name) {
  if (PrivateDirectory("/run/" + name)) return "/run/" + name;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime != nullptr && *runtime == '/' && PrivateDirectory(std::string(runtime) + "/" + name))
    return std::string(runtime) + "/" + name;
  const std::string tmp = "/tmp/" + name + "-" + std::to_string(getuid());
  PrivateDirectory(tmp);  // when even this fails, ProcessClaim::Take refuses a planted lock file
  return tmp;
}

std::string LockFileName(const std::string& key) {
  std::string name = key;
  for (char& c : name) {
    const bool kept = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '-' || c == '_';
    if (!kept) c = '_';
  }
  return name;
}

bool ProcessClaim::Take(const std::string& lock_path, const std::string& what, std::string* error) {
  Release();
  // Never through a link: the pid is written into the file, which must be the lock itself.
  fd_ = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) {
    *error = what + ": " + lock_path + ": " + std::strerror(errno);
    return false;
  }
  // A lock file a neighbour planted (in a directory others may write) is refused before anything
  // is written into it.
  struct stat st {};
  if (fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != geteuid()) {
    *error = what + ": " + lock_path + " is not a file of this user; remove it";
    Release();
    return false;
  }
  // An flock belongs to the open file: the kernel drops it when the last descriptor closes, which
  // a process's death does too. So a held lock is a living owner, whatever its pid says.
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int saved = errno;
    char pid[16] = {};
    const ssize_t n = pread(fd_, pid, sizeof(pid) - 1, 0);
    *error = what + " is in use" +
             (n > 0 ? " by process " + std::string(pid, static_cast<size_t>(n)) : std::string()) +
             " (" + lock_path + " is locked" +
             (saved == EWOULDBLOCK ? "" : ": " + std::string(std::strerror(saved))) + ")";
    Release();
    return false;
  }
  const std::string pid = std::to_string(getpid());
  if (ftruncate(fd_, 0) != 0 || pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    *error = what + ": " + lock_path + ": " + std::strerror(errno);
    Release();
    return false;
  }
  return true;
}

void ProcessClaim::Release() {
  if (fd_ >= 0) close(fd_);  // drops the lock
  fd_ = -1;
}

}  // namespace palpa::hosted
