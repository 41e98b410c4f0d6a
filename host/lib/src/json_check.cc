// JSON validation with the failing field named.
#include "palpa/host/json_check.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace palpa::host {
namespace {

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%g", v);
  return b;
}

}  // namespace

std::optional<std::string> ReadTextFile(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error != nullptr) *error = path + ": cannot be read";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
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
