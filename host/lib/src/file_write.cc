// Files written whole or not at all: the host library's entry to the one writer.
#include "palpa/host/file_write.h"

#include "palpa/hal/linux/append_file.h"
#include "palpa/hal/linux/atomic_file.h"

namespace palpa::host {

Outcome WriteFileWhole(const std::string& path, std::string_view bytes) {
  hal::Done written = hal::linux_files::WriteFileWhole(path, bytes);
  if (!written.ok()) return Outcome::Fail(written.status, std::move(written.message));
  return {};
}

Outcome AppendFileLine(const std::string& path, std::string_view line) {
  bool repaired = false;
  hal::Done appended = hal::linux_files::AppendLine(path, line, &repaired);
  if (!appended.ok()) return Outcome::Fail(appended.status, std::move(appended.message));
  Outcome done;
  if (repaired) done.notes.push_back(path + ": cut off a torn last line an interrupted write left");
  return done;
}

}  // namespace palpa::host
