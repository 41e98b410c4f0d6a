// A board configuration as JSON: what `palpa config show` prints and `config load|set` read.
#include "palpa/host/config_json.h"

#include <stdexcept>
#include <string>

#include "palpa/host/json_fields.h"

namespace palpa::host {

namespace pp = palpa::protocol;

json ConfigToJson(const core::BoardConfig& c) {
  json j;
  j["board"] = MessageToJson(c.board);
  j["lines"] = json::array();
  for (uint8_t i = 0; i < c.line_count; ++i) j["lines"].push_back(MessageToJson(c.lines[i]));
  j["fingers"] = json::array();
  for (uint8_t f = 0; f < c.finger_count; ++f) j["fingers"].push_back(MessageToJson(c.fingers[f]));
  return j;
}

namespace {

void ApplyInPlace(const json& j, core::BoardConfig& config) {
  if (!j.is_object()) throw std::runtime_error("expected an object with board, lines, fingers");
  for (const auto& [key, value] : j.items()) {
    if (key != "board" && key != "lines" && key != "fingers")
      throw std::runtime_error("unknown section '" + key + "'");
  }
  auto merge = [](json base, const json& patch, const std::string& where) {
    if (!patch.is_object()) throw std::runtime_error(where + ": expected an object");
    for (const auto& [k, v] : patch.items()) {
      if (!base.contains(k)) throw std::runtime_error(where + ": unknown field '" + k + "'");
      base[k] = v;
    }
    return base;
  };
  if (j.contains("board")) {
    try {
      config.board = MessageFromJson<pp::ConfigureBoard>(
          merge(MessageToJson(config.board), j["board"], "board"));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("board: ") + e.what());
    }
  }
  for (const char* section : {"lines", "fingers"}) {
    if (!j.contains(section)) continue;
    if (!j[section].is_array())
      throw std::runtime_error(std::string(section) + ": expected an array");
    for (size_t n = 0; n < j[section].size(); ++n) {
      const json& entry = j[section][n];
      const std::string where = std::string(section) + "[" + std::to_string(n) + "]";
      const char* index_key = section[0] == 'l' ? "line" : "finger";
      if (!entry.is_object() || !entry.contains(index_key) ||
          !entry[index_key].is_number_unsigned()) {
        throw std::runtime_error(where + ": needs \"" + index_key + "\" (0-based, as on the wire)");
      }
      const size_t index = entry[index_key].get<size_t>();
      try {
        if (section[0] == 'l') {
          if (index > config.line_count || index >= pp::kMaxLines)
            throw std::runtime_error("line " + std::to_string(index) + " does not exist");
          config.lines[index] = MessageFromJson<pp::ConfigureLine>(
              merge(MessageToJson(config.lines[index]), entry, where));
          if (index == config.line_count) ++config.line_count;
        } else {
          if (index > config.finger_count || index >= pp::kMaxFingers)
            throw std::runtime_error("finger " + std::to_string(index) + " does not exist");
          config.fingers[index] = MessageFromJson<pp::ConfigureFinger>(
              merge(MessageToJson(config.fingers[index]), entry, where));
          if (index == config.finger_count) ++config.finger_count;
        }
      } catch (const std::exception& e) {
        throw std::runtime_error(where + ": " + e.what());
      }
    }
  }
}

}  // namespace

void ApplyConfigJson(const json& patch, core::BoardConfig& config) {
  core::BoardConfig changed = config;  // all or nothing: a later field may still be refused
  ApplyInPlace(patch, changed);
  config = changed;
}

}  // namespace palpa::host
