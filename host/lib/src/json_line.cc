// The line a JSON path's value starts on: a scan of the text that follows objects, arrays and
// keys as the parser does (strings with their escapes skipped whole), recording each value's line.
#include "json_line.h"

#include <map>
#include <vector>

namespace palpa::host {
namespace {

/// Every value's path → its line. Stops (returning what it has) at anything malformed.
std::map<std::string, int> ValueLines(const std::string& text) {
  std::map<std::string, int> lines;
  std::vector<JsonPathLevel> levels;
  int line = 1;
  bool expect_key = false;
  auto value_starts = [&] { lines.emplace(JsonPathText(levels), line); };
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ':') continue;
    if (c == '"') {
      std::string s;
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;  // an escape: never the closing quote
        if (i < text.size()) s += text[i];
      }
      if (expect_key && !levels.empty()) {
        levels.back().key = s;
        expect_key = false;
      } else {
        value_starts();
      }
    } else if (c == '{' || c == '[') {
      value_starts();
      levels.push_back(JsonPathLevel{c == '[', "", 0});
      expect_key = c == '{';
    } else if (c == '}' || c == ']') {
      if (levels.empty()) return lines;
      levels.pop_back();
      expect_key = false;
    } else if (c == ',') {
      if (levels.empty()) return lines;
      if (levels.back().array) {
        ++levels.back().index;
      } else {
        expect_key = true;
      }
    } else {  // a number, true, false, null: its start
      value_starts();
      while (i + 1 < text.size() &&
             std::string(",]} \t\r\n").find(text[i + 1]) == std::string::npos)
        ++i;
    }
  }
  return lines;
}

}  // namespace

std::string JsonPathText(const std::vector<JsonPathLevel>& levels) {
  std::string path;
  for (const JsonPathLevel& l : levels) {
    if (l.array) {
      path += "[" + std::to_string(l.index) + "]";
    } else if (!l.key.empty()) {
      path += (path.empty() ? "" : ".") + l.key;
    }
  }
  return path;
}

int JsonPathLine(const std::string& text, const std::string& path) {
  const std::map<std::string, int> lines = ValueLines(text);
  for (std::string p = path;;) {
    if (const auto it = lines.find(p); it != lines.end()) return it->second;
    if (p.empty()) return 0;
    const size_t cut = p.find_last_of(".[");
    p = cut == std::string::npos ? "" : p.substr(0, cut);
  }
}

std::string WithJsonLine(const std::string& text, const std::string& message) {
  const size_t colon = message.find(": ");
  if (colon == std::string::npos || message.compare(0, 5, "line ") == 0 ||
      message.find(' ') < colon)
    return message;
  const int line = JsonPathLine(text, message.substr(0, colon));
  return line > 0 ? "line " + std::to_string(line) + ": " + message : message;
}

}  // namespace palpa::host
