// A link-time seam on fsync for tests of files flushed to disk: the library's calls land here
// first, are recorded while g_record_fsyncs is set, then go on to the C library. Include it in
// exactly one source file of a test program (it defines fsync).
#pragma once

#include <dlfcn.h>
#include <sys/stat.h>

#include <cstddef>

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
