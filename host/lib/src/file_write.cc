// Files written whole or not at all: the host library's entry to the one writer.
#include "palpa/host/file_write.h"

#include "palpa/hal/linux/append_file.h"
#include "palpa/hal/linux/atomic_file.h"

namespace palpa::host {

Outcome WriteFileWhole(const std::string& path, std::string_view bytes) {
  std::string error;
  if (!hal::linux_files::WriteFileWhole(path, bytes, &error))
    return Outcome::Fail(Status::kIoError, std::move(error));
  return {};
}

Outcome AppendFileLine(const std::string& path, std::string_view line) {
  std::string error;
  bool repaired = false;
  if (!hal::linux_files::AppendLine(path, line, &error, &repaired))
    return Outcome::Fail(Status::kIoError, std::move(error));
  Outcome done;
  if (repaired) done.notes.push_back(path + ": cut off a torn last line an interrupted write left");
  return done;
}

}  // namespace palpa::host
