// JSON views of protocol messages (golden files, configuration files, the CLI), driven by each
// message's Fields().
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "palpa/protocol/catalog.h"

namespace palpa::host {

using nlohmann::json;
namespace pp = palpa::protocol;

std::string ToHex(const uint8_t* data, size_t size);
std::vector<uint8_t> FromHex(const std::string& hex);

/// Message → JSON object (enums as names, byte fields as hex, text as strings).
class JsonWriter {
 public:
  json out = json::object();

  template <typename T>
  void Field(const char* name, const T& v, pp::Bound<T> = {}, pp::Bound<T> = {}) {
    out[name] = v;
  }
  void Flag(const char* name, const bool& v) { out[name] = v; }
  template <typename E>
  void Enum(const char* name, const E& v) {
    out[name] = EnumNames(E{})[static_cast<size_t>(v)];
  }
  template <typename T, size_t N>
  void Array(const char* name, const std::array<T, N>& items, const uint8_t& count) {
    json list = json::array();
    for (size_t i = 0; i < count; ++i) {
      if constexpr (std::is_arithmetic_v<T>) {
        list.push_back(items[i]);
      } else {
        JsonWriter element;
        T::Fields(element, items[i]);
        list.push_back(element.out);
      }
    }
    out[name] = list;
  }
  template <size_t N>
  void Bytes(const char* name, const std::array<uint8_t, N>& data, const uint8_t& size) {
    out[name] = ToHex(data.data(), size);
  }
  template <size_t N>
  void Fixed(const char* name, const std::array<uint8_t, N>& data) {
    out[name] = ToHex(data.data(), N);
  }
  template <size_t N>
  void Text(const char* name, const std::array<char, N>& text) {
    size_t n = 0;
    while (n < N && text[n] != '\0') ++n;
    out[name] = std::string(text.data(), n);
  }
};

/// JSON object → message. Throws std::runtime_error naming the field on a missing key, an unknown
/// key, a wrong type or a value that does not fit the field.
class JsonReader {
 public:
  explicit JsonReader(const json& in) : in_(in) {
    if (!in_.is_object()) throw std::runtime_error("fields: expected an object");
  }

  template <typename T>
  void Field(const char* name, T& v) {
    Field(name, v, std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max());
  }
  /// The field's wire range applies here too, so a value the codec would refuse is refused with
  /// its name now (and code that trusts decoded ranges, like validation, never sees it).
  template <typename T>
  void Field(const char* name, T& v, pp::Bound<T> lo, pp::Bound<T> hi) {
    ReadNumber(name, At(name), v);
    if constexpr (std::is_same_v<T, float>) {
      if (!std::isfinite(v)) Fail(name, "not a finite float");
    }
    if (!(v >= lo && v <= hi)) {
      Fail(name, ToText(v) + " is outside " + ToText(lo) + " … " + ToText(hi));
    }
  }
  void Flag(const char* name, bool& v) {
    const json& j = At(name);
    if (!j.is_boolean()) Fail(name, "expected true or false");
    v = j.get<bool>();
  }
  template <typename E>
  void Enum(const char* name, E& v) {
    const json& j = At(name);
    if (!j.is_string()) Fail(name, "expected an enumerator name");
    const std::string text = j.get<std::string>();
    const char* const* names = EnumNames(E{});
    for (uint64_t i = 0; i < pp::EnumCount<E>(); ++i) {
      if (text == names[i]) {
        v = static_cast<E>(i);
        return;
      }
    }
    Fail(name, "unknown enumerator '" + text + "'");
  }
  template <typename T, size_t N>
  void Array(const char* name, std::array<T, N>& items, uint8_t& count) {
    const json& j = At(name);
    if (!j.is_array()) Fail(name, "expected an array");
    if (j.size() > N) Fail(name, "more than " + std::to_string(N) + " items");
    count = static_cast<uint8_t>(j.size());
    for (size_t i = 0; i < j.size(); ++i) {
      if constexpr (std::is_arithmetic_v<T>) {
        ReadNumber(name, j[i], items[i]);
      } else {
        JsonReader element(j[i]);
        T::Fields(element, items[i]);
        element.Finish();
      }
    }
  }
  template <size_t N>
  void Bytes(const char* name, std::array<uint8_t, N>& data, uint8_t& size) {
    const std::vector<uint8_t> bytes = Hex(name);
    if (bytes.size() > N) Fail(name, "more than " + std::to_string(N) + " bytes");
    std::copy(bytes.begin(), bytes.end(), data.begin());
    size = static_cast<uint8_t>(bytes.size());
  }
  template <size_t N>
  void Fixed(const char* name, std::array<uint8_t, N>& data) {
    const std::vector<uint8_t> bytes = Hex(name);
    if (bytes.size() != N) Fail(name, "expected exactly " + std::to_string(N) + " bytes");
    std::copy(bytes.begin(), bytes.end(), data.begin());
  }
  template <size_t N>
  void Text(const char* name, std::array<char, N>& text) {
    const json& j = At(name);
    if (!j.is_string()) Fail(name, "expected a string");
    const std::string s = j.get<std::string>();
    if (s.size() >= N) Fail(name, "longer than " + std::to_string(N - 1) + " characters");
    text.fill('\0');
    std::copy(s.begin(), s.end(), text.begin());
  }

  /// Every key of the object must have been read.
  void Finish() const {
    for (const auto& item : in_.items()) {
      if (!seen_.count(item.key())) Fail(item.key(), "unknown field");
    }
  }

 private:
  template <typename T>
  static void ReadNumber(const std::string& name, const json& j, T& v) {
    if constexpr (std::is_same_v<T, float>) {
      if (!j.is_number()) Fail(name, "expected a number");
      v = static_cast<float>(j.get<double>());
    } else if constexpr (std::is_same_v<T, uint64_t>) {
      if (!j.is_number_unsigned()) Fail(name, "expected an unsigned integer");
      v = j.get<uint64_t>();
    } else {
      if (!j.is_number_integer()) Fail(name, "expected an integer");
      const int64_t raw = j.get<int64_t>();
      if (raw < static_cast<int64_t>(std::numeric_limits<T>::lowest()) ||
          raw > static_cast<int64_t>(std::numeric_limits<T>::max())) {
        Fail(name, "does not fit its wire type");
      }
      v = static_cast<T>(raw);
    }
  }
  const json& At(const std::string& name) {
    if (!in_.contains(name)) Fail(name, "missing");
    seen_.insert(name);
    return in_.at(name);
  }
  std::vector<uint8_t> Hex(const char* name) {
    const json& j = At(name);
    if (!j.is_string()) Fail(name, "expected a hex string");
    try {
      return FromHex(j.get<std::string>());
    } catch (const std::exception& e) {
      Fail(name, e.what());
    }
    return {};
  }
  template <typename T>
  static std::string ToText(T v) {
    if constexpr (std::is_same_v<T, float>) {
      char text[32];
      std::snprintf(text, sizeof(text), "%g", static_cast<double>(v));
      return text;
    } else {
      return std::to_string(v);
    }
  }
  [[noreturn]] static void Fail(const std::string& name, const std::string& what) {
    throw std::runtime_error("field '" + name + "': " + what);
  }

  const json& in_;
  std::set<std::string> seen_;
};

template <class M>
json MessageToJson(const M& m) {
  JsonWriter w;
  M::Fields(w, m);
  return w.out;
}

template <class M>
M MessageFromJson(const json& j) {
  M m{};
  JsonReader r(j);
  M::Fields(r, m);
  r.Finish();
  return m;
}

/// Calls f.template operator()<M>() for the catalog message named `name`; false if none.
template <class F>
bool WithMessageNamed(const std::string& name, F&& f) {
  bool found = false;
  pp::ForEachMessage(pp::Catalog{}, [&]<class M>() {
    if (!found && name == M::kInfo.name) {
      found = true;
      f.template operator()<M>();
    }
  });
  return found;
}

}  // namespace palpa::host
