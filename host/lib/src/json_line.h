// Where a JSON path's value starts in its text: so that a file's error can name the line as well
// as the field ("line 12: blocks[1].repetitions: ...").
#pragma once

#include <string>
#include <vector>

namespace palpa::host {

/// One level of a JSON path being followed: an array's index, or an object's key.
struct JsonPathLevel {
  bool array = false;
  std::string key;   ///< object: the key of the value being read
  size_t index = 0;  ///< array: the index of the value being read
};
/// "board.host_timeout_us", "curve[2].kpa" (json_check's names); empty at the top.
std::string JsonPathText(const std::vector<JsonPathLevel>& levels);

/// The 1-based line of the value at `path` ("blocks[1].repetitions", as json_check names fields)
/// in `text`, or of the deepest part of the path that is there (a missing field: its object);
/// 0 when the text is not one well-formed document.
int JsonPathLine(const std::string& text, const std::string& path);

/// "line N: MESSAGE" when MESSAGE starts with a field's path ("a.b[2]: ...") found in `text`;
/// MESSAGE as it was otherwise (a syntax error already names its line).
std::string WithJsonLine(const std::string& text, const std::string& message);

}  // namespace palpa::host
