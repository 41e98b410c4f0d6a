// JSON validation with the failing field named.
#include "palpa/host/json_check.h"
#include "json_line.h"
#include "number_text.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

namespace palpa::host {
namespace {

/// Follows the parser through the document so that a value it refuses is named by its path,
/// and stops it at kMaxJsonDepth.
class PathTracker {
 public:
  struct TooDeep {};

  bool operator()(int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        if (depth >= kMaxJsonDepth) throw TooDeep{};
        levels_.push_back(JsonPathLevel{event == Event::array_start, "", 0});
        break;
      case Event::key:
        levels_.back().key = parsed.get<std::string>();
        break;
      case Event::object_end:
      case Event::array_end:
        levels_.pop_back();
        Next();
        break;
      case Event::value:
        Next();
        break;
    }
    return true;
  }

  /// "board.host_timeout_us", "curve[2].kpa"; empty at the top.
  std::string Path() const { return JsonPathText(levels_); }

 private:
  void Next() {
    if (!levels_.empty() && levels_.back().array) ++levels_.back().index;
  }
  std::vector<JsonPathLevel> levels_;
};

/// nlohmann's message without its "[json.exception.parse_error.101] " code.
std::string Words(const std::exception& e) {
  const std::string what = e.what();
  const size_t code_end = what.rfind("] ", what.find(' '));
  return code_end == std::string::npos ? what : what.substr(code_end + 2);
}

}  // namespace

Result<nlohmann::json> ParseJson(const std::string& text) {
  PathTracker tracker;
  auto fail = [&](const std::string& why) -> Result<nlohmann::json> {
    const std::string path = tracker.Path();
    return {Status::kInvalidArgument, (path.empty() ? "" : path + ": ") + why};
  };
  try {
    return nlohmann::json::parse(text, std::ref(tracker));
  } catch (const PathTracker::TooDeep&) {
    return fail("nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  } catch (const nlohmann::json::out_of_range& e) {
    if (e.id == 406) {  // "number overflow parsing '1e400'"
      const std::string what = e.what();
      const size_t quote = what.find('\'');
      const std::string number =
          quote == std::string::npos ? "" : what.substr(quote, what.rfind('\'') - quote + 1);
      return fail("the number " + number + " is beyond the range of a double");
    }
    return fail("not valid JSON: " + Words(e));
  } catch (const nlohmann::json::exception& e) {
    return fail("not valid JSON: " + Words(e));
  }
}

Result<nlohmann::json> ReadJsonFile(const std::string& path, const FileLimits& limits) {
  return ReadAndParse(path, limits, ParseJson);
}

JsonObject::JsonObject(const nlohmann::json& j, std::string path, std::set<std::string> known)
    : j_(j), path_(std::move(path)) {
  if (!j.is_object())
    throw JsonInvalid((path_.empty() ? std::string("document") : path_) + ": must be an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!known.count(it.key())) throw JsonInvalid(Join(it.key()) + ": unknown field");
  }
}

bool JsonObject::Has(const char* key) const { return j_.contains(key) && !j_.at(key).is_null(); }

const nlohmann::json& JsonObject::At(const char* key) const {
  if (!Has(key)) throw JsonInvalid(Join(key) + ": missing");
  return j_.at(key);
}

double JsonObject::Number(const char* key, double lo, double hi) const {
  const nlohmann::json& v = At(key);
  if (!v.is_number()) throw JsonInvalid(Join(key) + ": must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi) {
    throw JsonInvalid(Join(key) + ": " + Num(d) + " is outside " + Num(lo) + " … " + Num(hi));
  }
  return d;
}

long JsonObject::Integer(const char* key, long lo, long hi) const {
  const nlohmann::json& v = At(key);
  if (!v.is_number_integer()) throw JsonInvalid(Join(key) + ": must be an integer");
  const long n = v.get<long>();
  if (n < lo || n > hi) {
    throw JsonInvalid(Join(key) + ": " + std::to_string(n) + " is outside " + std::to_string(lo) +
                      " … " + std::to_string(hi));
  }
  return n;
}

std::string JsonObject::Text(const char* key) const {
  const nlohmann::json& v = At(key);
  if (!v.is_string() || v.get<std::string>().empty())
    throw JsonInvalid(Join(key) + ": must be a non-empty string");
  return v.get<std::string>();
}

bool JsonObject::Flag(const char* key) const {
  const nlohmann::json& v = At(key);
  if (!v.is_boolean()) throw JsonInvalid(Join(key) + ": must be true or false");
  return v.get<bool>();
}

std::string JsonObject::Choice(const char* key, const std::set<std::string>& choices) const {
  const std::string v = Text(key);
  if (choices.count(v)) return v;
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw JsonInvalid(Join(key) + ": \"" + v + "\" is not one of " + list);
}

const nlohmann::json& JsonObject::List(const char* key, size_t lo, size_t hi) const {
  const nlohmann::json& v = At(key);
  if (!v.is_array()) throw JsonInvalid(Join(key) + ": must be an array");
  if (v.size() < lo || v.size() > hi) {
    throw JsonInvalid(Join(key) + ": has " + std::to_string(v.size()) + " entries, needs " +
                      std::to_string(lo) + " … " + std::to_string(hi));
  }
  return v;
}

std::string JsonObject::Join(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

std::string JsonObject::Item(const char* key, size_t i) const {
  return Join(key) + "[" + std::to_string(i) + "]";
}

}  // namespace palpa::host
