// A protocol text field as a string, read no further than the field: one helper for every reader.
#pragma once

#include <array>
#include <cstddef>
#include <cstring>
#include <string>

namespace palpa::host {

/// The characters before the first NUL, at most N: bounded even where a field was not checked.
template <size_t N>
std::string FieldText(const std::array<char, N>& text) {
  return std::string(text.data(), strnlen(text.data(), N));
}

}  // namespace palpa::host
