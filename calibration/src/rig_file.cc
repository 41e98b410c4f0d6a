// Rig description files and opening their devices.
#include "palpa/calibration/rig_file.h"

#include "palpa/calibration/modbus_devices.h"
#include "palpa/calibration/netft.h"
#include "palpa/host/json_check.h"

namespace palpa::calibration {
namespace {

using host::JsonInvalid;
using host::JsonObject;
using nlohmann::json;

/// The device's "driver" ("" when absent), checked to be a string.
std::string Driver(const JsonObject& o, const char* key) {
  const json& device = o.At(key);
  if (!device.is_object()) throw JsonInvalid(o.Join(key) + ": must be an object");
  if (!device.contains("driver")) return "";
  if (!device.at("driver").is_string())
    throw JsonInvalid(o.Join(key) + ".driver: must be a string (modbus or netft)");
  return device.at("driver").get<std::string>();
}

RegisterMap Device(const JsonObject& o, const char* key, const std::vector<std::string>& required) {
  const std::string driver = Driver(o, key);
  json device = o.At(key);
  if (driver != "modbus") {
    throw JsonInvalid(o.Join(key) + ".driver: \"" + driver +
                      "\" is not a driver this build has (modbus)");
  }
  device.erase("driver");
  auto map = ParseRegisterMap(device, o.Join(key), required);
  if (!map.ok()) throw JsonInvalid(map.message);
  return std::move(map.value);
}

const char kSimRigJson[] =
#include "sim_rig_json.inc"
    ;

}  // namespace

RigDescription SimRigDescription(const std::string& modbus_uri) {
  json j = json::parse(kSimRigJson);
  j["stage"]["address"] = modbus_uri;
  j["force_sensor"]["address"] = modbus_uri;
  return ParseRigDescription(j.dump()).value;  // the shipped file is checked by the tests
}

host::Result<RigDescription> ParseRigDescription(const std::string& text) {
  const auto parsed = host::ParseJson(text);
  if (!parsed.ok()) return parsed.outcome();
  try {
    const json& j = parsed.value;
    JsonObject o(j, "", {"name", "comment", "stage", "force_sensor", "force_noise_n", "limits"});
    RigDescription rig;
    rig.name = o.Text("name");
    if (o.Has("force_noise_n")) rig.force_noise_n = o.Number("force_noise_n", 1e-6, 10);
    rig.stage = Device(o, "stage", kStageRegisters);
    if (Driver(o, "force_sensor") == "netft") {
      const json& force = o.At("force_sensor");
      JsonObject f(force, "force_sensor",
                   {"driver", "address", "counts_per_force", "axis", "sign", "timeout_ms"});
      auto address = ParseNetFtAddress(f.Text("address"));
      if (!address.ok()) throw JsonInvalid("force_sensor.address: " + address.message);
      NetFtConfig* c = &address.value;
      if (f.Has("counts_per_force")) c->counts_per_force = f.Number("counts_per_force", 1, 1e9);
      if (f.Has("axis")) {
        const std::string axis = f.Choice("axis", {"fx", "fy", "fz"});
        c->axis = axis == "fx" ? 0 : axis == "fy" ? 1 : 2;
      }
      if (f.Has("sign")) {
        c->sign = f.Number("sign", -1, 1);
        if (c->sign != 1 && c->sign != -1) throw JsonInvalid("force_sensor.sign: must be 1 or -1");
      }
      if (f.Has("timeout_ms")) c->timeout_ms = static_cast<int>(f.Integer("timeout_ms", 10, 10000));
      rig.netft = *c;
    } else {
      rig.force = Device(o, "force_sensor", kForceRegisters);
    }
    if (o.Has("limits")) {
      JsonObject l(o.At("limits"), "limits",
                   {"max_force_n", "min_position_mm", "max_position_mm", "retract_mm"});
      if (l.Has("max_force_n")) rig.limits.max_force_n = l.Number("max_force_n", 0.01, 50);
      if (l.Has("min_position_mm"))
        rig.limits.min_position_mm = l.Number("min_position_mm", -100, 100);
      if (l.Has("max_position_mm"))
        rig.limits.max_position_mm = l.Number("max_position_mm", -100, 500);
      if (l.Has("retract_mm")) rig.limits.retract_mm = l.Number("retract_mm", -100, 500);
      if (rig.limits.min_position_mm >= rig.limits.max_position_mm) {
        throw JsonInvalid("limits.min_position_mm: must be below max_position_mm");
      }
    }
    return rig;
  } catch (const std::exception& e) {  // JsonInvalid names the field
    return {host::Status::kInvalidArgument, e.what()};
  }
}

host::Result<RigDescription> LoadRigDescription(const std::string& path) {
  return host::ReadAndParse(path, kRigFileLimits, ParseRigDescription);
}

host::Result<RigDevices> OpenRigDevices(const RigDescription& rig) {
  auto stage = ModbusDevice::Open(rig.stage);
  if (!stage.ok()) return {stage.status, "stage: " + stage.message};
  RigDevices d;
  d.stage = std::make_unique<ModbusStage>(std::move(stage.value));
  if (rig.netft) {
    auto force = NetFtForceSensor::Open(*rig.netft);
    if (!force.ok()) return {force.status, "force sensor: " + force.message};
    d.force = std::move(force.value);
  } else {
    auto force = ModbusDevice::Open(rig.force);
    if (!force.ok()) return {force.status, "force sensor: " + force.message};
    d.force = std::make_unique<ModbusForceSensor>(std::move(force.value));
  }
  return d;
}

}  // namespace palpa::calibration
