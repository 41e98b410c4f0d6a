// Files written whole or not at all (see file_write.h).
#include "palpa/host/file_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace palpa::host {
namespace {

bool Fail(std::string* error, const std::string& what) {
  if (error != nullptr) *error = what + ": " + std::strerror(errno);
  return false;
}

}  // namespace

bool WriteFileWhole(const std::string& path, std::string_view bytes, std::string* error) {
  // Beside the target (rename does not cross file systems), named per process so two writers of
  // one file do not share a temporary.
  const std::string temporary = path + ".part" + std::to_string(getpid());
  const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Fail(error, path + ": cannot be created");
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    written += static_cast<size_t>(n);
  }
  bool ok = written == bytes.size() || Fail(error, path + ": write failed");
  // On disk before the rename: otherwise a power cut can leave the new name with no contents.
  ok = ok && (fsync(fd) == 0 || Fail(error, path + ": flush failed"));
  ok = (close(fd) == 0 || Fail(error, path + ": write failed")) && ok;
  ok = ok && (std::rename(temporary.c_str(), path.c_str()) == 0 ||
              Fail(error, path + ": cannot replace it"));
  if (!ok) unlink(temporary.c_str());
  return ok;
}

}  // namespace palpa::host
