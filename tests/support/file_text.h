// A whole file read into a string, for tests that check what a program or a writer left on disk.
#pragma once

#include <fstream>
#include <iterator>
#include <string>

namespace palpa::testing {

/// Everything in the file at `path` ("" when it cannot be read).
inline std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace palpa::testing
