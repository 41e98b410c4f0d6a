// Parsing of finger and line arguments: every mistake is named before anything is sent.
#include <cmath>
#include <cstdlib>

#include "cli.h"

namespace palpa::cli {

bool ParseNumber(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return *end == '\0' && std::isfinite(out);
}

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool SplitIndex(const std::string& arg, const char* what, uint8_t count, uint8_t& index,
                std::string& value, std::string* error) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) {
    *error = "'" + arg + "': expected " + what + "=VALUE, e.g. 1=L2";
    return false;
  }
  double n = 0;
  if (!ParseNumber(arg.substr(0, eq), n) || n != std::floor(n) || n < 1 || n > count) {
    *error = "'" + arg + "': " + what + " must be a number from 1 to " + std::to_string(count);
    return false;
  }
  index = static_cast<uint8_t>(n - 1);
  value = arg.substr(eq + 1);
  if (value.empty()) {
    *error = "'" + arg + "': the value is missing";
    return false;
  }
  return true;
}

}  // namespace

bool ParseFingerArgument(const std::string& arg, uint8_t finger_count, host::FingerRequest& out,
                         std::string* error) {
  std::string value;
  if (!SplitIndex(arg, "finger", finger_count, out.finger, value, error)) return false;
  struct Suffix {
    const char* text;
    host::TargetKind kind;
  };
  const Suffix suffixes[] = {{"N/mm", host::TargetKind::kStiffnessNPerMm},
                             {"kPa", host::TargetKind::kPressureKpa},
                             {"mm", host::TargetKind::kDeformationMm}};
  double n = 0;
  if (value[0] == 'L' || value[0] == 'l') {
    if (!ParseNumber(value.substr(1), n) || n != std::floor(n) || n < 0) {
      *error = "'" + arg + "': a level is L followed by 0, 1, 2 ...";
      return false;
    }
    out.request = host::Request{host::TargetKind::kLevel, n};
    return true;
  }
  for (const Suffix& s : suffixes) {
    if (!EndsWith(value, s.text)) continue;
    if (!ParseNumber(value.substr(0, value.size() - std::string(s.text).size()), n)) {
      *error = "'" + arg + "': '" + value + "' is not a number followed by " + s.text;
      return false;
    }
    out.request = host::Request{s.kind, n};
    return true;
  }
  if (!ParseNumber(value, n)) {
    *error = "'" + arg + "': expected L<level>, a number 0..1, <mm>mm, <N/mm>N/mm or <kPa>kPa";
    return false;
  }
  if (n < 0 || n > 1) {
    *error =
        "'" + arg +
        "': a plain number is a normalised stiffness from 0 to 1 (add a unit for anything else)";
    return false;
  }
  out.request = host::Request{host::TargetKind::kNormalized, n};
  return true;
}

bool ParseLineArgument(const std::string& arg, uint8_t line_count, std::pair<uint8_t, double>& out,
                       std::string* error) {
  std::string value;
  if (!SplitIndex(arg, "line", line_count, out.first, value, error)) return false;
  if (EndsWith(value, "kPa")) value = value.substr(0, value.size() - 3);
  if (!ParseNumber(value, out.second)) {
    *error = "'" + arg + "': expected a pressure in kPa, e.g. 2=30 or 6=-40kPa";
    return false;
  }
  return true;
}

}  // namespace palpa::cli
