// Files read whole within limits (see file_read.h).
#include "palpa/host/file_read.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace palpa::host {
namespace {

std::string TooLarge(const std::string& path, const FileLimits& limits, const std::string& size) {
  return path + ": larger than the " + SizeText(limits.max_bytes) + " limit for a " + limits.kind +
         (size.empty() ? "" : " (" + size + ")");
}

}  // namespace

std::string SizeText(size_t bytes) {
  if (bytes >= 1024 * 1024 && bytes % (1024 * 1024) == 0)
    return std::to_string(bytes / (1024 * 1024)) + " MiB";
  if (bytes >= 1024 && bytes % 1024 == 0) return std::to_string(bytes / 1024) + " KiB";
  return std::to_string(bytes) + " bytes";
}

Result<std::string> ReadFileWhole(const std::string& path, const FileLimits& limits) {
  auto fail = [](std::string why, Status status = Status::kInvalidArgument) -> Result<std::string> {
    return {status, std::move(why)};
  };
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    const Status status = errno == ENOENT ? Status::kNotFound : Status::kIoError;
    return fail(path + ": cannot be read: " + std::strerror(errno), status);
  }
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    return fail(path + ": not a regular file (a " + limits.kind + " is read only from one)");
  }
  if (static_cast<unsigned long long>(st.st_size) > limits.max_bytes) {
    close(fd);
    return fail(TooLarge(path, limits, SizeText(static_cast<size_t>(st.st_size))));
  }
  // Read one byte past the limit: a file that grew since fstat is caught all the same.
  std::string text(static_cast<size_t>(st.st_size) + 1, '\0');
  size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (text.size() > limits.max_bytes) break;
      text.resize(std::min(text.size() * 2, limits.max_bytes + 1));
    }
    const ssize_t n = read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = std::strerror(errno);
      close(fd);
      return fail(path + ": cannot be read: " + why, Status::kIoError);
    }
    if (n == 0) break;
    got += static_cast<size_t>(n);
  }
  close(fd);
  if (got > limits.max_bytes) return fail(TooLarge(path, limits, ""));
  text.resize(got);
  return text;
}

}  // namespace palpa::host
