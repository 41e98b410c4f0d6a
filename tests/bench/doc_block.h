// Benchmarks keep their latest figures in the docs: a block between two markers in a Markdown
// file, replaced whole on every run.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace palpa::bench {

/// Replaces the text between `<!-- NAME:begin -->` and `<!-- NAME:end -->` in the file at `path`;
/// false when the file or its markers are missing or it cannot be written.
inline bool ReplaceBlock(const std::string& path, const std::string& name,
                         const std::string& block) {
  std::ifstream in(path);
  if (!in) return false;
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string begin = "<!-- " + name + ":begin -->", end = "<!-- " + name + ":end -->";
  const size_t b = s.find(begin), e = s.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b) return false;
  s = s.substr(0, b + begin.size()) + "\n" + block + s.substr(e);
  return host::WriteFileWhole(path, s).ok();
}

}  // namespace palpa::bench
