// Files written whole or not at all, for every file palpa and palpa-sim write: a temporary made
// beside the target (a fresh name, created exclusively, so never through a planted link), with the
// replaced file's mode, flushed and renamed over the target, then the directory flushed.
#pragma once

#include <string>
#include <string_view>

#include "palpa/hal/linux/opened.h"

namespace palpa::hal::linux_files {

/// A file that appears at its path complete or not at all, even across a crash or power cut.
/// Open refuses a target that exists and is not a regular file (a symbolic link is neither
/// followed nor replaced) and creates the temporary `.NAME.XXXXXX.part` in the target's
/// directory: an unpredictable name opened with O_CREAT | O_EXCL | O_NOFOLLOW, so a link or file
/// planted beside the target is never written through. The temporary gets the replaced file's
/// permissions (a new file: 0666 less the umask). Commit writes what is buffered, flushes the
/// file to disk, renames it over the target and flushes the directory, so the new name survives
/// a power cut. Until Commit succeeds the old file is untouched; an AtomicFile destroyed or
/// abandoned before then removes its temporary. A process killed meanwhile cannot: its writer
/// holds an exclusive flock on the temporary until the rename, the kernel drops it with the
/// process, and the next Open of the same target removes the temporaries of its name whose lock
/// it can take (this user's regular files only, never a link), so a live writer's, in any
/// process, is never touched. Writes are buffered; the first failure is kept and reported by
/// Commit. Not thread-safe: callers that write from several threads lock.
class AtomicFile {
 public:
  AtomicFile() = default;
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// kIoError with "PATH: reason" when the temporary cannot be made.
  Done Open(const std::string& path);
  void Write(std::string_view bytes);
  /// kIoError naming the file and the reason when anything failed since Open; the temporary is
  /// removed then.
  Done Commit();
  /// Removes the temporary; the target is left as it was.
  void Abandon();

  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

 private:
  void Flush();
  void Fail(const std::string& what);

  std::string path_;
  std::string temporary_;
  int fd_ = -1;
  std::string buffer_;
  std::string failure_;  ///< the first failure since Open
};

/// Writes `bytes` to `path` through an AtomicFile; on failure (kIoError) the old file is untouched
/// and the message names the file and the reason.
Done WriteFileWhole(const std::string& path, std::string_view bytes);

}  // namespace palpa::hal::linux_files
