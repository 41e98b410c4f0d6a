// Reading and validating JSON documents so that every failure names the field by its path
// ("curve[2].kpa: ..."): parsing with a nesting cap and the path of a value the parser refuses,
// and getters that check type and range. Used by every JSON file palpa reads.
#pragma once

#include <set>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/file_read.h"

namespace palpa::host {

/// No file palpa reads nests deeper than a few levels; past this a document is refused before
/// it is built (nesting costs memory and recursion elsewhere).
inline constexpr int kMaxJsonDepth = 16;

/// Parses JSON text. Invalid argument on anything the parser refuses, named by the path of the
/// value it was reading: a syntax error ("not valid JSON at line 3, column 7: ..."), a number
/// no double holds ("board.host_timeout_us: the number 1e400 is beyond a double's range"), or
/// nesting deeper than kMaxJsonDepth.
Result<nlohmann::json> ParseJson(const std::string& text);

/// ReadFileWhole within `limits`, then ParseJson; errors start with "PATH: ".
Result<nlohmann::json> ReadJsonFile(const std::string& path, const FileLimits& limits);

/// A validation failure; what() starts with the JSON path of the field.
struct JsonInvalid : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// ParseJson, then `parse` (which throws JsonInvalid naming the field) on the document: either
/// failure an invalid-argument Result that names the field. What every JSON file reader does.
template <typename T, typename Parse>
Result<T> ParseJsonWith(const std::string& text, Parse parse) {
  const Result<nlohmann::json> j = ParseJson(text);
  if (!j.ok()) return j.outcome();
  try {
    return parse(j.value);
  } catch (const JsonInvalid& e) {
    return Result<T>{Status::kInvalidArgument, e.what()};
  }
}

/// An object being validated: every key must be one the schema knows; getters check type and
/// range and throw JsonInvalid naming the field.
class JsonObject {
 public:
  JsonObject(const nlohmann::json& j, std::string path, std::set<std::string> known);
  bool Has(const char* key) const;
  const nlohmann::json& At(const char* key) const;
  double Number(const char* key, double lo, double hi) const;
  long Integer(const char* key, long lo, long hi) const;
  std::string Text(const char* key) const;
  bool Flag(const char* key) const;  ///< a JSON true or false
  /// One of `choices`; the error lists them.
  std::string Choice(const char* key, const std::set<std::string>& choices) const;
  const nlohmann::json& List(const char* key, size_t lo, size_t hi) const;
  std::string Join(const std::string& key) const;
  std::string Item(const char* key, size_t i) const;

 private:
  const nlohmann::json& j_;
  std::string path_;
};

}  // namespace palpa::host
