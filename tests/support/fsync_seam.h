// A link-time seam on fsync for tests of files flushed to disk: the library's calls land here
// first, are recorded while g_record_fsyncs is set, then go on to the C library. Include it in
// exactly one source file of a test program (it defines fsync). With it, the fixtures' directory.
#pragma once

#include <dlfcn.h>
#include <sys/stat.h>

#include <stdlib.h>

#include <cstddef>
#include <filesystem>
#include <string>

/// What fsync was called on while recording: 'f' a regular file, 'd' a directory (a plain array:
/// the leak checker would count a container's storage).
inline bool g_record_fsyncs = false;
inline char g_fsynced[8];
inline size_t g_fsync_count = 0;

extern "C" int fsync(int fd) {
  using Fsync = int (*)(int);
  static const auto real = reinterpret_cast<Fsync>(dlsym(RTLD_NEXT, "fsync"));
  struct stat st;
  if (g_record_fsyncs && g_fsync_count < sizeof(g_fsynced) && fstat(fd, &st) == 0)
    g_fsynced[g_fsync_count++] = S_ISDIR(st.st_mode) ? 'd' : S_ISREG(st.st_mode) ? 'f' : '?';
  return real(fd);
}

/// A fresh directory under the temporary one for a test's files (empty when none can be made:
/// the test's writes then fail).
inline std::filesystem::path MakeTestDir(const char* prefix) {
  std::string pattern = (std::filesystem::temp_directory_path() / prefix).string() + "-XXXXXX";
  return mkdtemp(pattern.data()) != nullptr ? std::filesystem::path(pattern)
                                            : std::filesystem::path();
}

/// The directory removed with everything in it, and the fsync record reset.
inline void RemoveTestDir(const std::filesystem::path& dir) {
  g_record_fsyncs = false;
  g_fsync_count = 0;
  if (!dir.empty()) std::filesystem::remove_all(dir);
}
