// Files written whole or not at all: a temporary beside the target, flushed, renamed over it.
#pragma once

#include <string>
#include <string_view>

namespace palpa::host {

/// Writes `bytes` to `path` so that a reader finds the old file or the whole new one, never a
/// part, even across a crash or power cut; on failure the temporary is removed, the old file is
/// untouched and `error` (when given) names the file and the reason.
bool WriteFileWhole(const std::string& path, std::string_view bytes, std::string* error = nullptr);

}  // namespace palpa::host
