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

using hal::Done;
using hal::Opened;
using hal::Status;

/// Every refusal of the file: a field that is not what it should be.
constexpr Status kRefused = Status::kBadValue;

/// One object's fields, each optional; every refusal is "WHERE.KEY: expected ...", kept in the
/// object (refusal()) for its parser to return.
class Object {
 public:
  Object(const json& object, std::string where) : object_(object), where_(std::move(where)) {}

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
    refusal_ = Where(key) + index + ": " + why;
    return false;
  }
  /// Fail's words as the parser's answer.
  Done Refuse(const std::string& key, const std::string& index, const std::string& why) {
    Fail(key, index, why);
    return refusal();
  }
  bool refused() const { return !refusal_.empty(); }
  /// The last refusal, or done when none.
  Done refusal() const { return refused() ? Done(kRefused, refusal_) : Done(); }
  const json& object() const { return object_; }

 private:
  const json& object_;
  std::string where_;
  std::string refusal_;
};

Done ParseGpio(const json& gpio, BoardFile& f) {
  Object o(gpio, "gpio");
  if (!o.OnlyKnown(
          {"supply_enable", "dump_enable", "pump_enable", "valves", "estop", "estop_active"}) ||
      !o.Line("supply_enable", &f.supply_enable) || !o.Line("dump_enable", &f.dump_enable) ||
      !o.Line("pump_enable", &f.pump_enable) || !o.Line("estop", &f.estop)) {
    return o.refusal();
  }
  std::string active = "high";
  if (!o.Text("estop_active", &active)) return o.refusal();
  if (active != "high" && active != "low")
    return o.Refuse("estop_active", "", "expected high or low");
  f.estop_active_high = active == "high";
  if (const auto it = gpio.find("valves"); it != gpio.end()) {
    if (!it->is_array()) return o.Refuse("valves", "", "expected an array of CHIP:LINE");
    for (size_t i = 0; i < it->size(); ++i) {
      const std::string index = "[" + std::to_string(i) + "]";
      if (!(*it)[i].is_string()) return o.Refuse("valves", index, "expected CHIP:LINE");
      f.valves.push_back((*it)[i].get<std::string>());
      if (!o.CheckLine("valves", index, f.valves.back())) return o.refusal();
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
      return o.Refuse(key, "", spec + " is already used by another field");
  }
  return {};
}

/// A refusal as ParseBoardFile's answer: an object's (refusal()) or the file's as a whole.
Opened<BoardFile> Refused(const Done& why) { return {why.status, why.message}; }
Opened<BoardFile> Refused(std::string why) { return {kRefused, std::move(why)}; }

}  // namespace

Opened<BoardFile> ParseBoardFile(const std::string& json_text) {
  const json root = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) return Refused("not a JSON object");
  BoardFile f;
  Object o(root, "");
  int board_id = 1;
  if (!o.OnlyKnown(
          {"board", "board_id", "link", "analog_module", "gpio", "watchdog", "realtime"}) ||
      !o.Text("board", &f.board) || !o.Int("board_id", 0, 0xFFFFFFFFll, &board_id)) {
    return Refused(o.refusal());
  }
  f.board_id = static_cast<uint32_t>(board_id);
  f.config = core::FindBoardConfig(f.board.c_str());
  if (f.config == nullptr) {
    std::string known;
    for (uint8_t i = 0; i < core::kBoardConfigCount; ++i)
      known += std::string(" ") + core::kBoardConfigs[i].name;
    return Refused("board: unknown board configuration '" + f.board + "' (known:" + known + ")");
  }
  if (!root.contains("analog_module"))
    return Refused("analog_module: required (the regulators' commands and the sensors)");
  // The module's own parser, on its object alone: its refusals name analog_module's fields.
  auto module =
      hal::linux_aio::ParseModbusAioConfig(json{{"analog_module", root["analog_module"]}}.dump());
  if (!module.ok()) return {module.status, module.message};
  f.module = module.value;
  // A child that is not an object is the root's refusal (Object::Child), checked below.
  if (const json* link = o.Child("link")) {
    Object l(*link, "link");
    if (!l.OnlyKnown({"listen", "baud"}) || !l.Text("listen", &f.listen) ||
        !l.Int("baud", 1200, 4000000, &f.baud)) {
      return Refused(l.refusal());
    }
    if (f.listen.rfind("tcp:", 0) != 0 && f.listen.rfind("pty:", 0) != 0 &&
        f.listen.rfind("tty:", 0) != 0 && f.listen != "usb" && f.listen.rfind("usb:", 0) != 0) {
      return Refused(
          l.Refuse("listen", "", "expected tcp:HOST:PORT, pty:PATH, tty:DEVICE, usb or usb:UDC"));
    }
  }
  if (o.refused()) return Refused(o.refusal());
  if (const json* gpio = o.Child("gpio")) {
    if (const Done parsed = ParseGpio(*gpio, f); !parsed.ok()) return Refused(parsed);
  }
  if (const json* wd = o.Child("watchdog")) {
    Object w(*wd, "watchdog");
    if (!w.OnlyKnown({"device", "timeout_s"}) || !w.Text("device", &f.watchdog) ||
        !w.Int("timeout_s", 1, 600, &f.watchdog_timeout_s)) {
      return Refused(w.refusal());
    }
    if (f.watchdog.empty())
      return Refused(w.Refuse("device", "", "required in watchdog (e.g. /dev/watchdog)"));
  }
  if (const json* rt = o.Child("realtime")) {
    Object r(*rt, "realtime");
    if (!r.OnlyKnown({"priority"}) || !r.Int("priority", 0, 99, &f.rt_priority))
      return Refused(r.refusal());
  }
  if (o.refused()) return Refused(o.refusal());
  if (f.valves.size() > f.config->line_count) {
    return Refused("gpio.valves: " + std::to_string(f.valves.size()) + " valves, but board " +
                   f.board + " has " + std::to_string(f.config->line_count) + " lines");
  }
  if (const Done fits = FitsTheModule(*f.config, f.board, f.module); !fits.ok())
    return Refused(fits);
  return f;
}

Opened<BoardFile> LoadBoardFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return {Status::kIoError, path + ": cannot read"};
  std::stringstream text;
  text << in.rdbuf();
  Opened<BoardFile> f = ParseBoardFile(text.str());
  if (!f.ok()) f.message = path + ": " + f.message;
  return f;
}

}  // namespace palpa::linux_board
