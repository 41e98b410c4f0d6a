// A board configuration as JSON: what `palpa config show` prints and `config load|set` read.
#include "palpa/host/config_json.h"

#include <stdexcept>
#include <string>

#include "palpa/host/json_fields.h"

namespace palpa::host {

namespace pp = palpa::protocol;

namespace {

/// A finger's line_b reads null where it has none (the wire's 0xFF).
json FingerToJson(const pp::ConfigureFinger& finger) {
  json j = MessageToJson(finger);
  if (finger.line_b == pp::kNoLine) j["line_b"] = nullptr;
  return j;
}

/// `base` with `patch`'s fields in place; an unknown field is refused with the known ones listed.
json Merge(json base, const json& patch, const char* index_key) {
  if (!patch.is_object()) throw std::runtime_error("expected an object");
  for (const auto& [k, v] : patch.items()) {
    if (!base.contains(k)) {
      std::string known;
      for (const auto& [name, value] : base.items()) {
        if (index_key == nullptr || name != index_key) known += (known.empty() ? "" : ", ") + name;
      }
      throw std::runtime_error("unknown field '" + k + "' (the fields: " + known + ")");
    }
    base[k] = v;
  }
  return base;
}

pp::ConfigureFinger FingerFromJson(json j) {
  if (j.contains("line_b") && j["line_b"].is_null()) j["line_b"] = pp::kNoLine;
  return MessageFromJson<pp::ConfigureFinger>(j);
}

/// One entry of "lines" or "fingers" (its index inside) onto `config`; throws naming the field.
void ApplyEntry(pp::ConfigSection section, size_t index, const json& entry,
                core::BoardConfig& config) {
  if (section == pp::ConfigSection::kBoard) {
    config.board =
        MessageFromJson<pp::ConfigureBoard>(Merge(MessageToJson(config.board), entry, nullptr));
  } else if (section == pp::ConfigSection::kLine) {
    if (index > config.line_count || index >= pp::kMaxLines)
      throw std::runtime_error("line " + std::to_string(index) + " does not exist");
    config.lines[index] = MessageFromJson<pp::ConfigureLine>(
        Merge(MessageToJson(config.lines[index]), entry, "line"));
    if (index == config.line_count) ++config.line_count;
  } else {
    if (index > config.finger_count || index >= pp::kMaxFingers)
      throw std::runtime_error("finger " + std::to_string(index) + " does not exist");
    config.fingers[index] =
        FingerFromJson(Merge(FingerToJson(config.fingers[index]), entry, "finger"));
    if (index == config.finger_count) ++config.finger_count;
  }
}

void ApplyInPlace(const json& j, core::BoardConfig& config) {
  if (!j.is_object()) throw std::runtime_error("expected an object with board, lines, fingers");
  for (const auto& [key, value] : j.items()) {
    if (key == kConfigNumberingKey) {
      if (value != kConfigNumbering) {
        throw std::runtime_error(std::string("\"") + kConfigNumberingKey +
                                 "\": lines and fingers " + "are numbered \"" + kConfigNumbering +
                                 "\" in configuration files");
      }
    } else if (key != "board" && key != "lines" && key != "fingers") {
      throw std::runtime_error("unknown section '" + key + "'");
    }
  }
  if (j.contains("board")) {
    try {
      ApplyEntry(pp::ConfigSection::kBoard, 0, j["board"], config);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("board: ") + e.what());
    }
  }
  for (const char* section : {"lines", "fingers"}) {
    if (!j.contains(section)) continue;
    if (!j[section].is_array())
      throw std::runtime_error(std::string(section) + ": expected an array");
    const bool lines = section[0] == 'l';
    for (size_t n = 0; n < j[section].size(); ++n) {
      const json& entry = j[section][n];
      const std::string where = std::string(section) + "[" + std::to_string(n) + "]";
      const char* index_key = lines ? "line" : "finger";
      if (!entry.is_object() || !entry.contains(index_key) ||
          !entry[index_key].is_number_unsigned()) {
        throw std::runtime_error(where + ": needs \"" + index_key + "\" (from 0, as on the wire)");
      }
      try {
        ApplyEntry(lines ? pp::ConfigSection::kLine : pp::ConfigSection::kFinger,
                   entry[index_key].get<size_t>(), entry, config);
      } catch (const std::exception& e) {
        throw std::runtime_error(where + ": " + e.what());
      }
    }
  }
}

}  // namespace

json ConfigToJson(const core::BoardConfig& c) {
  json j;
  j[kConfigNumberingKey] = kConfigNumbering;
  j["board"] = MessageToJson(c.board);
  j["lines"] = json::array();
  for (uint8_t i = 0; i < c.line_count; ++i) j["lines"].push_back(MessageToJson(c.lines[i]));
  j["fingers"] = json::array();
  for (uint8_t f = 0; f < c.finger_count; ++f) j["fingers"].push_back(FingerToJson(c.fingers[f]));
  return j;
}

void ApplyConfigJson(const json& patch, core::BoardConfig& config) {
  core::BoardConfig changed = config;  // all or nothing: a later field may still be refused
  ApplyInPlace(patch, changed);
  config = changed;
}

void SetConfigField(pp::ConfigSection section, uint8_t index, const std::string& field,
                    const json& value, core::BoardConfig& config) {
  const char* index_key = section == pp::ConfigSection::kLine     ? "line"
                          : section == pp::ConfigSection::kFinger ? "finger"
                                                                  : nullptr;
  if (index_key != nullptr && field == index_key)
    throw std::runtime_error("'" + field + "' is the entry's number, not a field to set");
  json entry = json::object();
  entry[field] = value;
  if (index_key != nullptr) entry[index_key] = index;
  core::BoardConfig changed = config;
  ApplyEntry(section, index, entry, changed);
  config = changed;
}

}  // namespace palpa::host
