// Files written whole or not at all: every file palpa writes goes through one writer (a fresh
// temporary created exclusively beside the target, the replaced file's mode, flushed, renamed over
// it, the directory flushed); see hal/linux/atomic_file.h for the rules.
#pragma once

#include <string>
#include <string_view>

#include "palpa/host/outcome.h"

namespace palpa::host {

/// Writes `bytes` to `path` so that a reader finds the old file or the whole new one, never a
/// part, even across a crash or power cut. The temporary is never written through a link planted
/// beside the target; a target that is a link, a directory or anything but a regular file is
/// refused. On failure (io_error) the temporary is removed, the old file is untouched and the
/// message names the file and the reason.
Outcome WriteFileWhole(const std::string& path, std::string_view bytes);

/// Appends one journal line (ending in its only '\n') to `path` and flushes it to disk before
/// returning, so a crash loses at most this line, left torn (without its newline); a torn last
/// line an earlier crash left is cut off first, with a note saying so. Links and anything but a
/// regular file are refused (io_error naming the file and the reason).
Outcome AppendFileLine(const std::string& path, std::string_view line);

}  // namespace palpa::host
