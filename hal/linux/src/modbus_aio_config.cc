// The Modbus analogue I/O module's configuration: strict JSON, every refusal naming its field.
#include "palpa/hal/linux/modbus_aio_config.h"

#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

namespace palpa::hal::linux_aio {
namespace {

using nlohmann::json;
constexpr const char* kSection = "analog_module";

// Reads one optional field; false when it is there but wrong, failure() then naming it.
class Fields {
 public:
  explicit Fields(const json& object) : object_(object) {}

  bool Int(const char* key, int lo, int hi, int* out) {
    const auto it = object_.find(key);
    if (it == object_.end()) return true;
    if (!it->is_number_integer() || it->get<long long>() < lo || it->get<long long>() > hi) {
      return Fail(key, "an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    }
    *out = static_cast<int>(it->get<long long>());
    return true;
  }
  bool Small(const char* key, int lo, int hi, uint8_t* out) {
    int v = *out;
    if (!Int(key, lo, hi, &v)) return false;
    *out = static_cast<uint8_t>(v);
    return true;
  }
  bool Text(const char* key, std::initializer_list<const char*> allowed, std::string* out) {
    const auto it = object_.find(key);
    if (it == object_.end()) return true;
    std::string names;
    for (const char* a : allowed) names += std::string(names.empty() ? "" : ", ") + a;
    if (!it->is_string() || it->get<std::string>().empty()) {
      return Fail(key, allowed.size() == 0 ? "a non-empty string" : "one of " + names);
    }
    if (allowed.size() == 0) {
      *out = it->get<std::string>();
      return true;
    }
    for (const char* a : allowed) {
      if (it->get<std::string>() == a) {
        *out = a;
        return true;
      }
    }
    return Fail(key, "one of " + names + ", not '" + it->get<std::string>() + "'");
  }
  bool OnlyKnown(const std::string& where, std::initializer_list<const char*> known) {
    for (const auto& [key, value] : object_.items()) {
      bool found = false;
      for (const char* k : known) found = found || key == k;
      if (!found) {
        failure_ = where + "." + key + ": unknown field";
        return false;
      }
    }
    return true;
  }
  void set_where(std::string where) { where_ = std::move(where); }
  const std::string& failure() const { return failure_; }

 private:
  bool Fail(const char* key, const std::string& expected) {
    failure_ = where_ + "." + key + ": expected " + expected;
    return false;
  }
  const json& object_;
  std::string failure_;
  std::string where_;
};

/// Every refusal of a configuration: kBadValue, the words naming the field.
Done Refused(std::string why) { return {Status::kBadValue, std::move(why)}; }

Done ParseChannels(const json& module, const char* key, bool inputs, ModbusAioConfig* c) {
  const std::string where = std::string(kSection) + "." + key;
  const auto it = module.find(key);
  if (it == module.end()) return {};
  if (!it->is_object()) return Refused(where + ": expected an object");
  Fields f(*it);
  f.set_where(where);
  const int most = c->module->max_channels;
  const bool ok = inputs ? f.OnlyKnown(where, {"count", "bits", "words_per_channel"}) &&
                               f.Small("count", 0, most, &c->input_count) &&
                               f.Small("bits", 1, 15, &c->input_bits) &&
                               f.Small("words_per_channel", 1, 2, &c->input_words)
                         : f.OnlyKnown(where, {"count", "bits"}) &&
                               f.Small("count", 0, most, &c->output_count) &&
                               f.Small("bits", 1, 15, &c->output_bits);
  return ok ? Done{} : Refused(f.failure());
}

Opened<ModbusAioConfig> Refusal(const Done& refused) { return {refused.status, refused.message}; }

}  // namespace

std::string ModbusAioConfig::Describe() const {
  return (tcp ? "tcp:" + host + ":" + std::to_string(port) : "rtu:" + host) + " unit " +
         std::to_string(unit);
}

Opened<ModbusAioConfig> ParseModbusAioConfig(const std::string& json_text) {
  const json root = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) return Refusal(Refused("not a JSON object"));
  Fields top(root);
  if (!top.OnlyKnown("(file)", {kSection})) return Refusal(Refused(top.failure()));
  const auto it = root.find(kSection);
  if (it == root.end() || !it->is_object()) {
    return Refusal(
        Refused(std::string(kSection) + ": expected an object (the analogue I/O module)"));
  }
  const json& m = *it;
  ModbusAioConfig c;
  Fields f(m);
  f.set_where(kSection);
  std::string module_class = c.module->name, transport = "tcp", parity = "N";
  if (!f.OnlyKnown(kSection, {"class", "transport", "host", "port", "device", "baud", "parity",
                              "data_bits", "stop_bits", "unit", "response_timeout_ms",
                              "watchdog_ms", "outputs", "inputs"}) ||
      !f.Text("class", {kBeckhoffEk9000.name}, &module_class) ||
      !f.Text("transport", {"tcp", "rtu"}, &transport)) {
    return Refusal(Refused(f.failure()));
  }
  c.tcp = transport == "tcp";
  // Fields of the other transport would be silently ignored: refuse them instead.
  static constexpr const char* kRtuOnly[] = {"device", "baud", "parity", "data_bits", "stop_bits"};
  static constexpr const char* kTcpOnly[] = {"host", "port"};
  for (const char* key : kRtuOnly) {
    if (c.tcp && m.contains(key)) {
      return Refusal(Refused(std::string(kSection) + "." + key + ": not a field of transport '" +
                             transport + "'"));
    }
  }
  for (const char* key : kTcpOnly) {
    if (!c.tcp && m.contains(key)) {
      return Refusal(Refused(std::string(kSection) + "." + key + ": not a field of transport '" +
                             transport + "'"));
    }
  }
  if (!c.tcp) c.host.clear();
  const bool ok = (c.tcp ? f.Text("host", {}, &c.host) && f.Int("port", 1, 65535, &c.port)
                         : f.Text("device", {}, &c.host) && f.Int("baud", 1200, 1000000, &c.baud) &&
                               f.Text("parity", {"N", "E", "O"}, &parity) &&
                               f.Int("data_bits", 7, 8, &c.data_bits) &&
                               f.Int("stop_bits", 1, 2, &c.stop_bits)) &&
                  f.Int("unit", c.tcp ? 0 : 1, 247, &c.unit) &&
                  f.Int("response_timeout_ms", 1, 5000, &c.response_timeout_ms) &&
                  // The EK9000 takes up to one minute; below the tick's own period it would trip.
                  f.Int("watchdog_ms", 10, 60000, &c.watchdog_ms);
  if (!ok) return Refusal(Refused(f.failure()));
  for (const bool inputs : {false, true}) {
    const Done channels = ParseChannels(m, inputs ? "inputs" : "outputs", inputs, &c);
    if (!channels.ok()) return Refusal(channels);
  }
  if (!c.tcp && c.host.empty())
    return Refusal(Refused(std::string(kSection) + ".device: required with transport 'rtu'"));
  c.parity = parity[0];
  if (c.watchdog_ms <= c.response_timeout_ms) {
    return Refusal(Refused(
        std::string(kSection) +
        ".watchdog_ms: must exceed response_timeout_ms, or one slow answer trips the module"));
  }
  return c;
}

Opened<ModbusAioConfig> LoadModbusAioConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) return {Status::kIoError, path + ": cannot read"};
  std::stringstream text;
  text << in.rdbuf();
  auto c = ParseModbusAioConfig(text.str());
  if (!c.ok()) c.message = path + ": " + c.message;
  return c;
}

}  // namespace palpa::hal::linux_aio
