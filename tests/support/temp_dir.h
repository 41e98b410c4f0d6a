// A fresh directory under /tmp for a test's files, named after what it holds.
#pragma once

#include <stdlib.h>

#include <string>

#include "CppUTest/TestHarness.h"

namespace palpa::testing {

/// A new, empty directory of this test's own: /tmp/PREFIX-XXXXXX.
inline std::string MakeTempDir(const std::string& prefix) {
  std::string pattern = "/tmp/" + prefix + "-XXXXXX";
  CHECK_TEXT(mkdtemp(pattern.data()) != nullptr, pattern.c_str());
  return pattern;
}

}  // namespace palpa::testing
