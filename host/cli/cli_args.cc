// Parsing of finger and line arguments: every mistake is named before anything is sent.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include "cli.h"

namespace palpa::cli {

bool ParseNumber(const std::string& text, double& out) {
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

bool OptionValue(const std::vector<std::string>& args, size_t i, std::string& value,
                 std::string* error) {
  if (i + 1 >= args.size() || (args[i + 1].rfind("--", 0) == 0 && args[i + 1].size() > 2)) {
    *error = args[i] + ": a value is missing";
    return false;
  }
  value = args[i + 1];
  return true;
}

std::string Suggest(const std::string& word, const std::vector<std::string>& candidates) {
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string w = lower(word);
  std::string best;
  size_t best_distance = 3;  // two edits at most: "sett", "stat", "monitr"
  for (const std::string& candidate : candidates) {
    const std::string c = lower(candidate);
    if (w.size() >= 3 && c.rfind(w, 0) == 0) return candidate;  // a prefix: "cal" → calibrate
    // Levenshtein distance, with a swap of two neighbours as one edit.
    std::vector<std::vector<size_t>> d(w.size() + 1, std::vector<size_t>(c.size() + 1));
    for (size_t i = 0; i <= w.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= c.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= w.size(); ++i) {
      for (size_t j = 1; j <= c.size(); ++j) {
        d[i][j] = std::min(
            {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (w[i - 1] == c[j - 1] ? 0 : 1)});
        if (i > 1 && j > 1 && w[i - 1] == c[j - 2] && w[i - 2] == c[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
    const size_t distance = d[w.size()][c.size()];
    if (distance < best_distance && distance < std::max<size_t>(c.size(), 2)) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

namespace {

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

bool SplitIndex(const std::string& arg, const char* what, uint8_t count, uint8_t& index,
                std::string& value, std::string* error) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) {
    *error = "'" + arg + "': expected " + what + "=VALUE, e.g. 1=L2";
    return false;
  }
  double n = 0;
  if (!ParseNumber(arg.substr(0, eq), n) || n != std::floor(n) || n < 1 || n > count) {
    *error = "'" + arg + "': " + what + " must be a whole number from 1" +
             (count < 255 ? " to " + std::to_string(count) : std::string(" (numbered from 1)"));
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
    if (!EndsWithIgnoringCase(value, s.text)) continue;
    const std::string number = value.substr(0, value.size() - std::string(s.text).size());
    if (!EndsWith(value, s.text)) {  // "10kpa", "1.2MM": units are spelled one way only
      *error = "'" + arg + "': unknown unit '" + value.substr(number.size()) + "' (did you mean " +
               number + s.text + "?)";
      return false;
    }
    if (!ParseNumber(number, n)) {
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
  if (EndsWithIgnoringCase(value, "kPa")) {
    const std::string number = value.substr(0, value.size() - 3);
    if (!EndsWith(value, "kPa")) {
      *error = "'" + arg + "': unknown unit '" + value.substr(number.size()) + "' (did you mean " +
               number + "kPa?)";
      return false;
    }
    value = number;
  }
  if (!ParseNumber(value, out.second)) {
    *error = "'" + arg + "': expected a pressure in kPa, e.g. 2=30 or 6=-40kPa";
    return false;
  }
  return true;
}

bool CheckDistinct(const std::vector<uint8_t>& indices, const std::vector<std::string>& args,
                   const char* what, std::string* error) {
  std::map<uint8_t, size_t> first;
  for (size_t i = 0; i < indices.size(); ++i) {
    const auto [at, fresh] = first.emplace(indices[i], i);
    if (!fresh) {
      *error = std::string(what) + " " + std::to_string(indices[i] + 1) + " is given twice ('" +
               args[at->second] + "' and '" + args[i] + "'): give each " + what + " once";
      return false;
    }
  }
  return true;
}

bool CheckOnBoard(const std::vector<uint8_t>& indices, uint8_t count, const char* what,
                  const std::string& board_name, std::string* error) {
  for (uint8_t index : indices) {
    if (index < count) continue;
    *error = std::string(what) + " " + std::to_string(index + 1) + ": this " + board_name +
             " board has " + what + "s 1 to " + std::to_string(count);
    return false;
  }
  return true;
}

}  // namespace palpa::cli
