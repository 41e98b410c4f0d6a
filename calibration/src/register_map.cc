// Register maps: parsing with the failing field named, and value encoding by type and order.
#include "palpa/calibration/register_map.h"

#include <cmath>
#include <cstring>
#include <regex>

#include "palpa/host/json_check.h"

namespace palpa::calibration {

const std::vector<std::string> kStageRegisters = {"position", "target", "speed", "command",
                                                  "moving"};
const std::vector<std::string> kForceRegisters = {"force"};

host::Result<ModbusAddress> ParseModbusAddress(const std::string& uri) {
  std::smatch m;
  ModbusAddress a;
  // Bounded digit counts: every number then fits an int, and the ranges below judge it.
  if (std::regex_match(uri, m, std::regex(R"(modbus-tcp://([^:/]+):(\d{1,6})/(\d{1,6}))"))) {
    a.tcp = true;
    a.host = m[1];
    a.port = std::stoi(m[2]);
    a.unit = std::stoi(m[3]);
  } else if (std::regex_match(
                 uri, m, std::regex(R"(modbus-rtu:(/[^?]+)\?baud=(\d{1,8})&unit=(\d{1,6}))"))) {
    a.tcp = false;
    a.host = m[1];
    a.baud = std::stoi(m[2]);
    a.unit = std::stoi(m[3]);
  } else {
    return {
        host::Status::kInvalidArgument,
        "'" + uri + "' is not modbus-tcp://HOST:PORT/UNIT or modbus-rtu:/dev/ttyX?baud=N&unit=U"};
  }
  if (a.port < 1 || a.port > 65535 || a.unit < 0 || a.unit > 247 || a.baud < 1200 ||
      a.baud > 4000000) {
    return {host::Status::kInvalidArgument,
            "'" + uri + "': port 1..65535, unit 0..247, baud 1200..4000000"};
  }
  return a;
}

const Register* RegisterMap::Find(const std::string& name) const {
  const auto it = registers.find(name);
  return it == registers.end() ? nullptr : &it->second;
}

std::vector<uint16_t> RegisterMap::Encode(const Register& r, double value) const {
  const double raw = value / r.scale;
  uint32_t bits = 0;
  switch (r.type) {
    case RegisterType::kU16:
      bits = static_cast<uint16_t>(std::lround(raw));
      break;
    case RegisterType::kI16:
      bits = static_cast<uint16_t>(static_cast<int16_t>(std::lround(raw)));
      break;
    case RegisterType::kU32:
      bits = static_cast<uint32_t>(std::llround(raw));
      break;
    case RegisterType::kI32:
      bits = static_cast<uint32_t>(static_cast<int32_t>(std::llround(raw)));
      break;
    case RegisterType::kF32: {
      const float f = static_cast<float>(raw);
      std::memcpy(&bits, &f, sizeof(bits));
      break;
    }
  }
  auto swap = [this](uint16_t w) {
    return byte_swap ? static_cast<uint16_t>((w >> 8) | (w << 8)) : w;
  };
  if (r.words() == 1) return {swap(static_cast<uint16_t>(bits))};
  const uint16_t high = swap(static_cast<uint16_t>(bits >> 16)),
                 low = swap(static_cast<uint16_t>(bits));
  return low_word_first ? std::vector<uint16_t>{low, high} : std::vector<uint16_t>{high, low};
}

double RegisterMap::Decode(const Register& r, const uint16_t* words) const {
  auto swap = [this](uint16_t w) {
    return byte_swap ? static_cast<uint16_t>((w >> 8) | (w << 8)) : w;
  };
  uint32_t bits = swap(words[0]);
  if (r.words() == 2) {
    const uint32_t first = swap(words[0]), second = swap(words[1]);
    bits = low_word_first ? (second << 16 | first) : (first << 16 | second);
  }
  double raw = 0;
  switch (r.type) {
    case RegisterType::kU16:
      raw = static_cast<uint16_t>(bits);
      break;
    case RegisterType::kI16:
      raw = static_cast<int16_t>(static_cast<uint16_t>(bits));
      break;
    case RegisterType::kU32:
      raw = bits;
      break;
    case RegisterType::kI32:
      raw = static_cast<int32_t>(bits);
      break;
    case RegisterType::kF32: {
      float f = 0;
      std::memcpy(&f, &bits, sizeof(f));
      raw = f;
      break;
    }
  }
  return raw * r.scale;
}

host::Result<RegisterMap> ParseRegisterMap(const nlohmann::json& j, const std::string& path,
                                           const std::vector<std::string>& required) {
  using host::JsonInvalid;
  using host::JsonObject;
  try {
    JsonObject o(j, path,
                 {"address", "byte_order", "word_order", "timeout_ms", "registers", "commands"});
    RegisterMap map;
    map.uri = o.Text("address");
    const auto address = ParseModbusAddress(map.uri);
    if (!address.ok()) throw JsonInvalid(o.Join("address") + ": " + address.message);
    map.address = address.value;
    if (o.Has("byte_order")) map.byte_swap = o.Choice("byte_order", {"big", "little"}) == "little";
    if (o.Has("word_order"))
      map.low_word_first = o.Choice("word_order", {"big", "little"}) == "little";
    if (o.Has("timeout_ms")) map.timeout_ms = static_cast<int>(o.Integer("timeout_ms", 10, 60000));
    const nlohmann::json& regs = o.At("registers");
    if (!regs.is_object()) throw JsonInvalid(o.Join("registers") + ": must be an object");
    for (auto it = regs.begin(); it != regs.end(); ++it) {
      const std::string where = o.Join("registers") + "." + it.key();
      JsonObject r(it.value(), where, {"table", "address", "type", "scale", "unit"});
      Register reg;
      reg.table = r.Choice("table", {"holding", "input"}) == "input" ? RegisterTable::kInput
                                                                     : RegisterTable::kHolding;
      reg.address = static_cast<int>(r.Integer("address", 0, 65535));
      const std::string type = r.Choice("type", {"uint16", "int16", "uint32", "int32", "float32"});
      reg.type = type == "uint16"   ? RegisterType::kU16
                 : type == "int16"  ? RegisterType::kI16
                 : type == "uint32" ? RegisterType::kU32
                 : type == "int32"  ? RegisterType::kI32
                                    : RegisterType::kF32;
      if (r.Has("scale")) {
        reg.scale = r.Number("scale", -1e9, 1e9);
        if (reg.scale == 0) throw JsonInvalid(where + ".scale: must not be 0");
      }
      if (r.Has("unit")) reg.unit = r.Text("unit");
      if (reg.address + reg.words() > 65536)
        throw JsonInvalid(where + ".address: the value runs past register 65535");
      map.registers[it.key()] = reg;
    }
    for (const std::string& name : required) {
      if (map.Find(name) == nullptr)
        throw JsonInvalid(o.Join("registers") + "." + name + ": missing (this device needs it)");
    }
    for (const char* writable : {"target", "speed", "command", "tare"}) {
      const Register* r = map.Find(writable);
      if (r != nullptr && r->table == RegisterTable::kInput) {
        throw JsonInvalid(o.Join("registers") + "." + writable +
                          ".table: input registers cannot be written");
      }
    }
    if (o.Has("commands")) {
      const nlohmann::json& c = o.At("commands");
      JsonObject co(c, o.Join("commands"), {"move", "stop", "tare"});
      for (const char* name : {"move", "stop", "tare"}) {
        if (co.Has(name)) map.commands[name] = static_cast<int>(co.Integer(name, 0, 65535));
      }
    }
    for (const char* name : {"move", "stop"}) {
      if (map.Find("command") != nullptr && !map.commands.count(name)) {
        throw JsonInvalid(o.Join("commands") + "." + name +
                          ": missing (the command register needs it)");
      }
    }
    if (map.Find("tare") != nullptr && !map.commands.count("tare")) {
      throw JsonInvalid(o.Join("commands") + ".tare: missing (the tare register needs it)");
    }
    return map;
  } catch (const host::JsonInvalid& e) {
    return {host::Status::kInvalidArgument, e.what()};
  } catch (const nlohmann::json::exception& e) {
    return {host::Status::kInvalidArgument, path + ": " + e.what()};
  }
}

}  // namespace palpa::calibration
