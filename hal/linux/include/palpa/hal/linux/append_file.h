// Journals appended a line at a time: each line written in one call and flushed to disk before the
// call returns, so a crash loses at most the line being written, which readers recognise as torn
// (it lacks its newline) and the next append cuts off.
#pragma once

#include <string>
#include <string_view>

#include "palpa/hal/linux/opened.h"

namespace palpa::hal::linux_files {

/// Appends `line` (which must end in '\n' and hold no other) to the regular file at `path`,
/// creating it (0666 less the umask; the directory then flushed too, so its name survives a power
/// cut). A link or anything but a regular file at `path` is refused, never followed. A final line
/// left torn by an earlier crash (no newline) is cut off first and `*repaired` set (when given);
/// then the line is written and the file flushed. On failure a status (kBadValue: not one line;
/// kIoError) and "PATH: reason"; lines before this one are never touched.
Done AppendLine(const std::string& path, std::string_view line, bool* repaired = nullptr);

}  // namespace palpa::hal::linux_files
