// A number as people read it in messages and files: the shortest of fixed and exponent ("%g").
#pragma once

#include <cstdio>
#include <string>

namespace palpa::host {

inline std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%g", v);
  return b;
}

/// With a fixed number of decimals ("%.*f"); "—" for NaN (a proportion of nothing).
inline std::string Fixed(double v, int decimals) {
  if (v != v) return "—";
  char b[48];
  std::snprintf(b, sizeof(b), "%.*f", decimals, v);
  return b;
}

}  // namespace palpa::host
