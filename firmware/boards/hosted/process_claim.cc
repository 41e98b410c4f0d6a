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
namespace {

bool UsableDirectory(const std::string& path) {
  mkdir(path.c_str(), 0755);  // EEXIST is fine; whether it is usable is asked next
  return access(path.c_str(), W_OK | X_OK) == 0;
}

}  // namespace

std::string RunDirectory(const std::string& name) {
  if (UsableDirectory("/run/" + name)) return "/run/" + name;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime != nullptr && *runtime == '/' && UsableDirectory(std::string(runtime) + "/" + name))
    return std::string(runtime) + "/" + name;
  const std::string tmp = "/tmp/" + name + "-" + std::to_string(getuid());
  UsableDirectory(tmp);  // when even this fails, the claim's open names the path and why
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
  fd_ = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    *error = what + ": " + lock_path + ": " + std::strerror(errno);
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
