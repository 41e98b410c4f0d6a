// Validation of JSON documents that names the failing field by its path ("curve[2].kpa: ...").
// Used by calibration files, rig descriptions and register maps.
#pragma once

#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace palpa::host {

/// A whole text file, or nullopt with "PATH: cannot be read" in *error.
std::optional<std::string> ReadTextFile(const std::string& path, std::string* error);

/// A validation failure; what() starts with the JSON path of the field.
struct JsonInvalid : std::runtime_error {
  using std::runtime_error::runtime_error;
};

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
