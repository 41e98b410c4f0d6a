// Files written whole or not at all: the host library's entry to the one writer.
#include "palpa/host/file_write.h"

#include "palpa/hal/linux/atomic_file.h"

namespace palpa::host {

Outcome WriteFileWhole(const std::string& path, std::string_view bytes) {
  std::string error;
  if (!hal::linux_files::WriteFileWhole(path, bytes, &error))
    return Outcome::Fail(Status::kIoError, std::move(error));
  return {};
}

}  // namespace palpa::host
