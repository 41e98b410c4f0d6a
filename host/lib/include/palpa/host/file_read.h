// Files read whole within limits: only regular files, each kind with a size cap, so a FIFO, a
// device or a giant file named like one of palpa's files is refused instead of waited on or
// swallowed. Every file palpa reads comes through here (docs/threat_model.md lists the caps).
#pragma once

#include <cstddef>
#include <string>

#include "palpa/host/outcome.h"

namespace palpa::host {

/// What palpa accepts of one kind of file.
struct FileLimits {
  const char* kind;  ///< for errors: "calibration file", "update package", ...
  size_t max_bytes;
};

/// The whole of a regular file of at most limits.max_bytes. Fails with "PATH: reason" when it
/// does not exist (not_found) or cannot be read (io_error), is not a regular file (never waited
/// on: a FIFO is opened without blocking and refused) or is larger than the limit (named, with the
/// kind of file; both invalid_argument).
Result<std::string> ReadFileWhole(const std::string& path, const FileLimits& limits);

/// ReadFileWhole, then `parse(text)` (returning a Result); any error starts "PATH: ".
template <class Parse>
auto ReadAndParse(const std::string& path, const FileLimits& limits, Parse parse)
    -> decltype(parse(std::string())) {
  const auto text = ReadFileWhole(path, limits);
  if (!text.ok()) return text.outcome();
  auto parsed = parse(text.value);
  if (!parsed.ok()) parsed.message = path + ": " + parsed.message;
  return parsed;
}

/// "1 MiB", "64 KiB", "300 bytes": a size for people.
std::string SizeText(size_t bytes);

}  // namespace palpa::host
