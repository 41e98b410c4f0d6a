// Checks on message text shared by the host tests: starts with, contains, saying both texts.
#pragma once

#include <string>

#include "CppUTest/TestHarness.h"

namespace palpa::testing {

inline bool StartsWith(const std::string& text, const std::string& head) {
  return text.rfind(head, 0) == 0;
}

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace palpa::testing

#define CHECK_STARTS(text, head) \
  CHECK_TEXT(palpa::testing::StartsWith(text, head), (std::string(head) + " <> " + (text)).c_str())
#define CHECK_CONTAINS(text, part)                 \
  CHECK_TEXT(palpa::testing::Contains(text, part), \
             (std::string(part) + " not in: " + (text)).c_str())
