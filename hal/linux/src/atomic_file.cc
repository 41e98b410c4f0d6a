// Files written whole or not at all (see atomic_file.h).
#include "palpa/hal/linux/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace palpa::hal::linux_files {
namespace {

constexpr size_t kBufferSize = 64 * 1024;
constexpr size_t kSuffixSize = 6;
constexpr char kPart[] = ".part";

std::string Reason() { return std::strerror(errno); }

/// Six characters from the kernel's random source: a name nobody can plant ahead of time.
std::string RandomSuffix() {
  static constexpr char kAlphabet[] =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  unsigned char bytes[kSuffixSize] = {};
  if (getrandom(bytes, sizeof(bytes), 0) != static_cast<ssize_t>(sizeof(bytes))) {
    // Only without a random source; O_EXCL still refuses whatever is already there.
    for (unsigned char& b : bytes) b = static_cast<unsigned char>(std::rand());
  }
  std::string s;
  for (unsigned char b : bytes) s.push_back(kAlphabet[b % (sizeof(kAlphabet) - 1)]);
  return s;
}

/// Whether `entry` is a temporary this class names for the file `name`: ".NAME.XXXXXX.part".
bool IsTemporaryOf(const std::string& entry, const std::string& name) {
  const size_t head = name.size() + 2;
  if (entry.size() != head + kSuffixSize + sizeof(kPart) - 1 ||
      entry.compare(1, name.size(), name) != 0 || entry[0] != '.' || entry[head - 1] != '.' ||
      entry.compare(head + kSuffixSize, std::string::npos, kPart) != 0)
    return false;
  for (size_t i = head; i < head + kSuffixSize; ++i) {
    if (!std::isalnum(static_cast<unsigned char>(entry[i]))) return false;
  }
  return true;
}

/// Whether `path` still names the file open as `fd` (not removed, not replaced).
bool StillNamed(int fd, const std::string& path) {
  struct stat held, named;
  return fstat(fd, &held) == 0 && lstat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
         held.st_ino == named.st_ino;
}

/// Removes the temporaries of `name` in `dir` that writers killed before Commit left behind. A
/// live writer holds an exclusive flock on its temporary from creating it until it is renamed,
/// and the kernel drops a lock with its process: a temporary whose lock can be taken has no
/// writer. Only this user's regular files of exactly that name shape are touched.
void RemoveStaleTemporaries(const std::string& dir, const std::string& name) {
  DIR* d = opendir(dir.empty() ? "." : dir.c_str());
  if (d == nullptr) return;  // then Open's own create says what is wrong
  while (const dirent* e = readdir(d)) {
    if (!IsTemporaryOf(e->d_name, name)) continue;
    const std::string path = dir + e->d_name;
    const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    struct stat st;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == geteuid() &&
        flock(fd, LOCK_EX | LOCK_NB) == 0 && StillNamed(fd, path))
      unlink(path.c_str());
    close(fd);
  }
  closedir(d);
}

const char* Kind(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISLNK(mode)) return "is a symbolic link (palpa neither follows nor replaces links)";
  return "is not a regular file";
}

}  // namespace

AtomicFile::~AtomicFile() { Abandon(); }

Done AtomicFile::Open(const std::string& path) {
  Abandon();
  path_ = path;
  failure_.clear();
  struct stat old;
  const bool replacing = lstat(path.c_str(), &old) == 0;
  if (replacing && !S_ISREG(old.st_mode)) {
    return {Status::kIoError, path + ": " + Kind(old.st_mode)};
  }
  const size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  // A new file is created as open(2) would create it (0666 less the umask); one that replaces
  // another starts private and takes the old file's permissions before anything is written.
  const mode_t create_mode = replacing ? 0600 : 0666;
  RemoveStaleTemporaries(dir, name);
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    temporary_ = dir + "." + name + "." + RandomSuffix() + kPart;
    fd_ =
        open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, create_mode);
    if (fd_ < 0 && errno != EEXIST) break;
    // Locked until renamed, so another writer's clean-up leaves it alone. Taken by such a
    // clean-up between the create and the lock (it then removes it): another name. A file system
    // without locks (ENOLCK) is left unlocked: no clean-up can lock it either.
    const bool taken = fd_ >= 0 && flock(fd_, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    if (fd_ >= 0 && (taken || !StillNamed(fd_, temporary_))) {
      close(fd_);
      fd_ = -1;
    }
  }
  if (fd_ < 0) {
    temporary_.clear();
    return {Status::kIoError, path + ": cannot be created: " + Reason()};
  }
  if (replacing && fchmod(fd_, old.st_mode & 0777) != 0) {
    const std::string why = path + ": cannot keep its mode: " + Reason();
    Abandon();
    return {Status::kIoError, why};
  }
  return {};
}

void AtomicFile::Fail(const std::string& what) {
  if (failure_.empty()) failure_ = path_ + ": " + what + ": " + Reason();
}

void AtomicFile::Flush() {
  size_t written = 0;
  while (written < buffer_.size() && failure_.empty()) {
    const ssize_t n = write(fd_, buffer_.data() + written, buffer_.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      Fail("write failed");
      break;
    }
    written += static_cast<size_t>(n);
  }
  buffer_.clear();
}

void AtomicFile::Write(std::string_view bytes) {
  if (fd_ < 0 || !failure_.empty()) return;
  buffer_.append(bytes);
  if (buffer_.size() >= kBufferSize) Flush();
}

Done AtomicFile::Commit() {
  if (fd_ < 0) {
    return {Status::kIoError, path_ + ": not open for writing"};
  }
  Flush();
  // On disk before the rename: otherwise a power cut can leave the new name with no contents.
  if (failure_.empty() && fsync(fd_) != 0) Fail("flush failed");
  const int lock = dup(fd_);  // the lock held past close (which reports errors) until the rename
  if (close(fd_) != 0) Fail("write failed");
  fd_ = -1;
  if (failure_.empty() && std::rename(temporary_.c_str(), path_.c_str()) != 0)
    Fail("cannot replace it");
  if (!failure_.empty()) unlink(temporary_.c_str());
  if (lock >= 0) close(lock);
  if (!failure_.empty()) {
    temporary_.clear();
    return {Status::kIoError, failure_};
  }
  temporary_.clear();
  // The rename lives in the directory: flush it too, or a power cut may undo it.
  const size_t slash = path_.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : path_.substr(0, slash + 1);
  int flush_errno = 0;
  const int dir_fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd < 0) {
    flush_errno = errno;
  } else {
    // EINVAL: this file system has no directory flush; there is nothing to wait for.
    if (fsync(dir_fd) != 0 && errno != EINVAL) flush_errno = errno;
    close(dir_fd);
  }
  if (flush_errno != 0) {
    return {Status::kIoError,
            path_ + ": written, but its directory was not flushed: " + std::strerror(flush_errno)};
  }
  return {};
}

void AtomicFile::Abandon() {
  if (!temporary_.empty()) unlink(temporary_.c_str());  // while still locked: it is ours
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
  temporary_.clear();
  buffer_.clear();
}

Done WriteFileWhole(const std::string& path, std::string_view bytes) {
  AtomicFile file;
  Done opened = file.Open(path);
  if (!opened.ok()) return opened;
  file.Write(bytes);
  return file.Commit();
}

}  // namespace palpa::hal::linux_files
