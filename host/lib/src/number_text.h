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

}  // namespace palpa::host
