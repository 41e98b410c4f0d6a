// Journals appended a line at a time (see append_file.h).
#include "palpa/hal/linux/append_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::hal::linux_files {
namespace {

/// Closes the descriptor however the append ends.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) close(fd);
  }
};

Done Fail(const std::string& path, const char* what) {
  return {Status::kIoError, path + ": " + what + ": " + std::strerror(errno)};
}

/// The length of the file up to and including its last newline (0 when it has none).
bool WholeLinesEnd(int fd, off_t size, off_t* end) {
  char buffer[4096];
  off_t at = size;
  while (at > 0) {
    const off_t chunk = static_cast<off_t>(sizeof(buffer));
    const off_t from = at > chunk ? at - chunk : 0;
    const auto want = static_cast<size_t>(at - from);
    if (pread(fd, buffer, want, from) != static_cast<ssize_t>(want)) return false;
    for (size_t i = want; i > 0; --i) {
      if (buffer[i - 1] == '\n') {
        *end = from + static_cast<off_t>(i);
        return true;
      }
    }
    at = from;
  }
  *end = 0;
  return true;
}

}  // namespace

Done AppendLine(const std::string& path, std::string_view line, bool* repaired) {
  if (repaired != nullptr) *repaired = false;
  if (line.empty() || line.back() != '\n' || line.find('\n') != line.size() - 1) {
    return {Status::kBadValue, path + ": a journal line must end in its only newline"};
  }
  struct stat st;
  const bool existed = lstat(path.c_str(), &st) == 0;
  if (existed && !S_ISREG(st.st_mode)) {
    return {Status::kIoError,
            path + (S_ISLNK(st.st_mode)
                        ? ": is a symbolic link (palpa neither follows nor replaces links)"
                        : ": is not a regular file")};
  }
  Fd f{open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666)};
  if (f.fd < 0) return Fail(path, "cannot be opened to append");
  if (fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return {Status::kIoError, path + ": is not a regular file"};
  }
  off_t end = 0;
  if (!WholeLinesEnd(f.fd, st.st_size, &end)) return Fail(path, "cannot be read");
  if (end != st.st_size) {
    if (ftruncate(f.fd, end) != 0) return Fail(path, "cannot cut its torn last line");
    if (repaired != nullptr) *repaired = true;
  }
  size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = write(f.fd, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int why = errno;
      const bool cut = ftruncate(f.fd, end) == 0;  // leave no part of this line behind
      errno = why;
      return Fail(path, cut ? "cannot be written" : "cannot be written (a part is left)");
    }
    done += static_cast<size_t>(n);
  }
  if (fsync(f.fd) != 0) return Fail(path, "cannot be flushed to disk");
  if (!existed) {
    const size_t slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash + 1);
    Fd d{open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
    if (d.fd < 0 || fsync(d.fd) != 0) return Fail(path, "its directory cannot be flushed");
  }
  return {};
}

}  // namespace palpa::hal::linux_files
