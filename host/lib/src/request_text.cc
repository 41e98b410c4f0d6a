// Reading finger requests from text: every mistake named, the unit meant suggested.
#include "palpa/host/request_text.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace palpa::host {
namespace {

Outcome Invalid(std::string why) { return Outcome::Fail(Status::kInvalidArgument, std::move(why)); }

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool EndsWithIgnoringCase(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (size_t i = 0; i < suffix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) !=
        std::tolower(static_cast<unsigned char>(suffix[i])))
      return false;
  }
  return true;
}

}  // namespace

bool ParseDecimal(const std::string& text, double& out) {
  // Decimal only: strtod alone would also take "0x1", "inf", "nan" and leading blanks.
  size_t i = 0;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  size_t digits = 0;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i, ++digits;
  if (i < text.size() && text[i] == '.') {
    ++i;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    size_t exponent = 0;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i, ++exponent;
    if (exponent == 0) return false;
  }
  if (i != text.size()) return false;
  out = std::strtod(text.c_str(), nullptr);
  return std::isfinite(out);
}

Result<Request> ParseRequestText(const std::string& value) {
  struct Suffix {
    const char* text;
    TargetKind kind;
  };
  const Suffix suffixes[] = {{"N/mm", TargetKind::kStiffnessNPerMm},
                             {"kPa", TargetKind::kPressureKpa},
                             {"mm", TargetKind::kDeformationMm}};
  double n = 0;
  if (!value.empty() && (value[0] == 'L' || value[0] == 'l')) {
    if (!ParseDecimal(value.substr(1), n) || n != std::floor(n) || n < 0) {
      return Invalid("a level is L followed by 0, 1, 2 ...");
    }
    return Request{TargetKind::kLevel, n};
  }
  for (const Suffix& s : suffixes) {
    if (!EndsWithIgnoringCase(value, s.text)) continue;
    const std::string number = value.substr(0, value.size() - std::string(s.text).size());
    if (!EndsWith(value, s.text)) {  // "10kpa", "1.2MM": units are spelled one way only
      return Invalid("unknown unit '" + value.substr(number.size()) + "' (did you mean " + number +
                     s.text + "?)");
    }
    if (!ParseDecimal(number, n)) {
      return Invalid("'" + value + "' is not a number followed by " + s.text);
    }
    return Request{s.kind, n};
  }
  if (!ParseDecimal(value, n)) {
    return Invalid("expected L<level>, a number 0..1, <mm>mm, <N/mm>N/mm or <kPa>kPa");
  }
  if (n < 0 || n > 1) {
    return Invalid(
        "a plain number is a normalised stiffness from 0 to 1 (add a unit for anything else)");
  }
  return Request{TargetKind::kNormalized, n};
}

Result<double> ParsePressureText(const std::string& value) {
  std::string number = value;
  if (EndsWithIgnoringCase(value, "kPa")) {
    number = value.substr(0, value.size() - 3);
    if (!EndsWith(value, "kPa")) {
      return Invalid("unknown unit '" + value.substr(number.size()) + "' (did you mean " + number +
                     "kPa?)");
    }
  }
  double kpa = 0;
  if (!ParseDecimal(number, kpa)) return Invalid("expected a pressure in kPa");
  return kpa;
}

}  // namespace palpa::host
