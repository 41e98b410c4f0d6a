// Parsing of finger and line arguments: every mistake is named before anything is sent.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include "cli.h"
#include "palpa/host/request_text.h"

namespace palpa::cli {
namespace {

/// A command-line mistake, named: nothing is sent.
host::Outcome Invalid(std::string why) {
  return host::Outcome::Fail(protocol::Status::kInvalidArgument, std::move(why));
}

}  // namespace

bool ParseNumber(const std::string& text, double& out) { return host::ParseDecimal(text, out); }

host::Result<std::string> OptionValue(const std::vector<std::string>& args, size_t i) {
  if (i + 1 >= args.size() || (args[i + 1].rfind("--", 0) == 0 && args[i + 1].size() > 2))
    return Invalid(args[i] + ": a value is missing");
  return args[i + 1];
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

/// "N=VALUE": the 0-based index N-1 (into `index`) and VALUE.
host::Result<std::string> SplitIndex(const std::string& arg, const char* what, uint8_t count,
                                     uint8_t& index) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) {
    return Invalid("'" + arg + "': expected " + what + "=VALUE, e.g. 1=L2");
  }
  double n = 0;
  if (!ParseNumber(arg.substr(0, eq), n) || n != std::floor(n) || n < 1 || n > count) {
    return Invalid(
        "'" + arg + "': " + what + " must be a whole number from 1" +
        (count < 255 ? " to " + std::to_string(count) : std::string(" (numbered from 1)")));
  }
  index = static_cast<uint8_t>(n - 1);
  std::string value = arg.substr(eq + 1);
  if (value.empty()) return Invalid("'" + arg + "': the value is missing");
  return value;
}

}  // namespace

host::Result<host::FingerRequest> ParseFingerArgument(const std::string& arg,
                                                      uint8_t finger_count) {
  host::FingerRequest out;
  const host::Result<std::string> split = SplitIndex(arg, "finger", finger_count, out.finger);
  if (!split.ok()) return split.outcome();
  const host::Result<host::Request> request = host::ParseRequestText(split.value);
  if (!request.ok()) return Invalid("'" + arg + "': " + request.message);
  out.request = request.value;
  return out;
}

host::Result<std::pair<uint8_t, double>> ParseLineArgument(const std::string& arg,
                                                           uint8_t line_count) {
  std::pair<uint8_t, double> out;
  const host::Result<std::string> split = SplitIndex(arg, "line", line_count, out.first);
  if (!split.ok()) return split.outcome();
  const host::Result<double> kpa = host::ParsePressureText(split.value);
  if (!kpa.ok()) {
    const bool not_a_number = kpa.message.rfind("expected", 0) == 0;
    return Invalid("'" + arg +
                   "': " + (not_a_number ? kpa.message + ", e.g. 2=30 or 6=-40kPa" : kpa.message));
  }
  out.second = kpa.value;
  return out;
}

host::Outcome CheckDistinct(const std::vector<uint8_t>& indices,
                            const std::vector<std::string>& args, const char* what) {
  std::map<uint8_t, size_t> first;
  for (size_t i = 0; i < indices.size(); ++i) {
    const auto [at, fresh] = first.emplace(indices[i], i);
    if (!fresh) {
      return Invalid(std::string(what) + " " + std::to_string(indices[i] + 1) +
                     " is given twice ('" + args[at->second] + "' and '" + args[i] +
                     "'): give each " + what + " once");
    }
  }
  return {};
}

host::Outcome CheckOnBoard(const std::vector<uint8_t>& indices, uint8_t count, const char* what,
                           const std::string& board_name) {
  for (uint8_t index : indices) {
    if (index < count) continue;
    return Invalid(std::string(what) + " " + std::to_string(index + 1) + ": this " + board_name +
                   " board has " + what + "s 1 to " + std::to_string(count));
  }
  return {};
}

}  // namespace palpa::cli
