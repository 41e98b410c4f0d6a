// palpa-linux-board's configuration file: strict JSON, every refusal naming its field.
#include "board_file.h"

#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "palpa/core/board_configs.h"

namespace palpa::linux_board {
namespace {

using nlohmann::json;

/// One object's fields, each optional; every refusal is "WHERE.KEY: expected ...".
class Object {
 public:
  Object(const json& object, std::string where, std::string* error)
      : object_(object), where_(std::move(where)), error_(error) {}

  bool OnlyKnown(std::initializer_list<const char*> known) {
    for (const auto& item : object_.items()) {
      bool found = false;
      for (const char* k : known) found = found || item.key() == k;
      if (!found) return Fail(item.key(), "", "unknown field");
    }
    return true;
  }
  bool Int(const char* key, long long lo, long long hi, int* out) {
    const auto it = object_.find(key);
    if (it == object_.end()) return true;
    if (!it->is_number_integer() || it->get<long long>() < lo || it->get<long long>() > hi)
      return Fail(key, "",
                  "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    *out = static_cast<int>(it->get<long long>());
    return true;
  }
  bool Text(const char* key, std::string* out) {
    const auto it = object_.find(key);
    if (it == object_.end()) return true;
    if (!it->is_string() || it->get<std::string>().empty())
      return Fail(key, "", "expected a non-empty string");
    *out = it->get<std::string>();
    return true;
  }
  /// A GPIO line: "CHIP:LINE" with a line number; the chip is looked up when the line is opened.
  bool Line(const char* key, std::string* out) {
    if (!Text(key, out)) return false;
    return out->empty() || CheckLine(key, "", *out);
  }
  bool CheckLine(const std::string& key, const std::string& index, const std::string& spec) {
    const size_t colon = spec.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size() ||
        spec.find_first_not_of("0123456789", colon + 1) != std::string::npos)
      return Fail(key, index, "expected CHIP:LINE (e.g. gpiochip0:17), not '" + spec + "'");
    return true;
  }
  const json* Child(const char* key) {
    const auto it = object_.find(key);
    if (it == object_.end()) return nullptr;
    if (!it->is_object()) {
      Fail(key, "", "expected an object");
      return nullptr;
    }
    return &*it;
  }
  std::string Where(const std::string& key) const {
    return where_ + (where_.empty() ? "" : ".") + key;
  }
  bool Fail(const std::string& key, const std::string& index, const std::string& why) {
    *error_ = Where(key) + index + ": " + why;
    return false;
  }
  const json& object() const { return object_; }

 private:
  const json& object_;
  std::string where_;
  std::string* error_;
};

bool ParseGpio(const json& gpio, BoardFile& f, std::string* error) {
  Object o(gpio, "gpio", error);
  if (!o.OnlyKnown(
          {"supply_enable", "dump_enable", "pump_enable", "valves", "estop", "estop_active"}) ||
      !o.Line("supply_enable", &f.supply_enable) || !o.Line("dump_enable", &f.dump_enable) ||
      !o.Line("pump_enable", &f.pump_enable) || !o.Line("estop", &f.estop)) {
    return false;
  }
  std::string active = "high";
  if (!o.Text("estop_active", &active)) return false;
  if (active != "high" && active != "low")
    return o.Fail("estop_active", "", "expected high or low");
  f.estop_active_high = active == "high";
  if (const auto it = gpio.find("valves"); it != gpio.end()) {
    if (!it->is_array()) return o.Fail("valves", "", "expected an array of CHIP:LINE");
    for (size_t i = 0; i < it->size(); ++i) {
      const std::string index = "[" + std::to_string(i) + "]";
      if (!(*it)[i].is_string()) return o.Fail("valves", index, "expected CHIP:LINE");
      f.valves.push_back((*it)[i].get<std::string>());
      if (!o.CheckLine("valves", index, f.valves.back())) return false;
    }
  }
  // One line driven twice would be two outputs fighting: refused, naming both uses.
  std::set<std::string> seen;
  std::vector<std::pair<std::string, std::string>> uses = {{"supply_enable", f.supply_enable},
                                                           {"dump_enable", f.dump_enable},
                                                           {"pump_enable", f.pump_enable},
                                                           {"estop", f.estop}};
  for (size_t i = 0; i < f.valves.size(); ++i)
    uses.push_back({"valves[" + std::to_string(i) + "]", f.valves[i]});
  for (const auto& [key, spec] : uses) {
    if (!spec.empty() && !seen.insert(spec).second)
      return o.Fail(key, "", spec + " is already used by another field");
  }
  return true;
}

}  // namespace

std::optional<BoardFile> ParseBoardFile(const std::string& json_text, std::string* error) {
  const json root = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) {
    *error = "not a JSON object";
    return std::nullopt;
  }
  error->clear();  // a child that is not an object says so here (Object::Child)
  BoardFile f;
  Object o(root, "", error);
  int board_id = 1;
  if (!o.OnlyKnown(
          {"board", "board_id", "link", "analog_module", "gpio", "watchdog", "realtime"}) ||
      !o.Text("board", &f.board) || !o.Int("board_id", 0, 0xFFFFFFFFll, &board_id)) {
    return std::nullopt;
  }
  f.board_id = static_cast<uint32_t>(board_id);
  f.config = core::FindBoardConfig(f.board.c_str());
  if (f.config == nullptr) {
    std::string known;
    for (uint8_t i = 0; i < core::kBoardConfigCount; ++i)
      known += std::string(" ") + core::kBoardConfigs[i].name;
    *error = "board: unknown board configuration '" + f.board + "' (known:" + known + ")";
    return std::nullopt;
  }
  if (!root.contains("analog_module")) {
    *error = "analog_module: required (the regulators' commands and the sensors)";
    return std::nullopt;
  }
  // The module's own parser, on its object alone: its refusals name analog_module's fields.
  auto module =
      hal::linux_aio::ParseModbusAioConfig(json{{"analog_module", root["analog_module"]}}.dump());
  if (!module.ok()) {
    *error = module.message;
    return std::nullopt;
  }
  f.module = module.value;
  if (const json* link = o.Child("link")) {
    Object l(*link, "link", error);
    if (!l.OnlyKnown({"listen", "baud"}) || !l.Text("listen", &f.listen) ||
        !l.Int("baud", 1200, 4000000, &f.baud)) {
      return std::nullopt;
    }
    if (f.listen.rfind("tcp:", 0) != 0 && f.listen.rfind("pty:", 0) != 0 &&
        f.listen.rfind("tty:", 0) != 0 && f.listen != "usb" && f.listen.rfind("usb:", 0) != 0) {
      l.Fail("listen", "", "expected tcp:HOST:PORT, pty:PATH, tty:DEVICE, usb or usb:UDC");
      return std::nullopt;
    }
  }
  if (!error->empty()) return std::nullopt;
  if (const json* gpio = o.Child("gpio"); gpio != nullptr && !ParseGpio(*gpio, f, error))
    return std::nullopt;
  if (const json* wd = o.Child("watchdog")) {
    Object w(*wd, "watchdog", error);
    if (!w.OnlyKnown({"device", "timeout_s"}) || !w.Text("device", &f.watchdog) ||
        !w.Int("timeout_s", 1, 600, &f.watchdog_timeout_s)) {
      return std::nullopt;
    }
    if (f.watchdog.empty()) {
      w.Fail("device", "", "required in watchdog (e.g. /dev/watchdog)");
      return std::nullopt;
    }
  }
  if (const json* rt = o.Child("realtime")) {
    Object r(*rt, "realtime", error);
    if (!r.OnlyKnown({"priority"}) || !r.Int("priority", 0, 99, &f.rt_priority))
      return std::nullopt;
  }
  if (!error->empty()) return std::nullopt;
  if (f.valves.size() > f.config->line_count) {
    *error = "gpio.valves: " + std::to_string(f.valves.size()) + " valves, but board " + f.board +
             " has " + std::to_string(f.config->line_count) + " lines";
    return std::nullopt;
  }
  if (!FitsTheModule(*f.config, f.board, f.module, error)) return std::nullopt;
  return f;
}

std::optional<BoardFile> LoadBoardFile(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot read";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  auto f = ParseBoardFile(text.str(), error);
  if (!f) *error = path + ": " + *error;
  return f;
}

}  // namespace palpa::linux_board
