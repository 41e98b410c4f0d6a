// Compile-time setters used by the generated board configurations: enumerators by name, text by
// value, numbers converted explicitly. A wrong name fails the build, never the board.
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/field_codec.h"

namespace palpa::core {

// Not constexpr on purpose: reaching it in a constant expression is a compile error whose
// message names this function.
inline void UnknownEnumeratorOrTextTooLong() {}

constexpr bool SameText(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) {
    ++a;
    ++b;
  }
  return *a == *b;
}

template <typename E>
requires std::is_enum_v<E>
constexpr void Set(E& field, const char* name) {
  const char* const* names = EnumNames(E{});
  for (uint64_t i = 0; i < protocol::EnumCount<E>(); ++i) {
    if (SameText(names[i], name)) {
      field = static_cast<E>(i);
      return;
    }
  }
  UnknownEnumeratorOrTextTooLong();
}

template <size_t N>
constexpr void Set(std::array<char, N>& field, const char* text) {
  size_t i = 0;
  for (; text[i] != '\0'; ++i) {
    if (i == N) {
      UnknownEnumeratorOrTextTooLong();
      return;
    }
    field[i] = text[i];
  }
  for (; i < N; ++i) field[i] = '\0';
}

template <typename T, typename V>
requires std::is_arithmetic_v<T> && std::is_arithmetic_v<V>
constexpr void Set(T& field, V value) { field = static_cast<T>(value); }

}  // namespace palpa::core
