// Files written whole or not at all: the host library's entry to the one writer.
#include "palpa/host/file_write.h"

#include "palpa/hal/linux/atomic_file.h"

namespace palpa::host {

bool WriteFileWhole(const std::string& path, std::string_view bytes, std::string* error) {
  return hal::linux_files::WriteFileWhole(path, bytes, error);
}

}  // namespace palpa::host
