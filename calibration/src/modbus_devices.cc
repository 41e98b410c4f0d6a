// Modbus stage and force sensor on libmodbus.
#include "palpa/calibration/modbus_devices.h"

#include <modbus.h>

#include <cerrno>

namespace palpa::calibration {

host::Result<std::unique_ptr<ModbusDevice>> ModbusDevice::Open(const RegisterMap& map) {
  const ModbusAddress& a = map.address;
  modbus_t* ctx = a.tcp ? modbus_new_tcp(a.host.c_str(), a.port)
                        : modbus_new_rtu(a.host.c_str(), a.baud, 'N', 8, 1);
  if (ctx == nullptr) return {Status::kUnavailable, map.uri + ": " + modbus_strerror(errno)};
  modbus_set_slave(ctx, a.unit);
  modbus_set_response_timeout(ctx, static_cast<uint32_t>(map.timeout_ms / 1000),
                              static_cast<uint32_t>(map.timeout_ms % 1000) * 1000);
  if (modbus_connect(ctx) != 0) {
    const std::string why = map.uri + ": cannot connect (" + modbus_strerror(errno) + ")";
    modbus_free(ctx);
    return {Status::kUnavailable, why};
  }
  return std::unique_ptr<ModbusDevice>(new ModbusDevice(map, ctx));
}

ModbusDevice::~ModbusDevice() {
  modbus_close(ctx_);
  modbus_free(ctx_);
}

RigStatus ModbusDevice::Failure(const std::string& what) {
  return RigStatus::Fail(Status::kUnavailable,
                         map_.uri + ": " + what + " (" + modbus_strerror(errno) + ")");
}

RigStatus ModbusDevice::Read(const std::string& name, double* value) {
  const Register* r = map_.Find(name);
  if (r == nullptr)
    return RigStatus::Fail(Status::kBadValue, map_.uri + ": no register '" + name + "' in the map");
  uint16_t words[2] = {};
  const int n = r->table == RegisterTable::kInput
                    ? modbus_read_input_registers(ctx_, r->address, r->words(), words)
                    : modbus_read_registers(ctx_, r->address, r->words(), words);
  if (n != r->words()) return Failure("reading " + name);
  *value = map_.Decode(*r, words);
  return {};
}

RigStatus ModbusDevice::Write(const std::string& name, double value) {
  const Register* r = map_.Find(name);
  if (r == nullptr)
    return RigStatus::Fail(Status::kBadValue, map_.uri + ": no register '" + name + "' in the map");
  const std::vector<uint16_t> words = map_.Encode(*r, value);
  if (modbus_write_registers(ctx_, r->address, r->words(), words.data()) != r->words())
    return Failure("writing " + name);
  return {};
}

RigStatus ModbusDevice::Command(const char* register_name, const char* command) {
  const auto it = map_.commands.find(command);
  if (it == map_.commands.end())
    return RigStatus::Fail(Status::kBadValue,
                           map_.uri + ": no '" + command + "' command in the map");
  return Write(register_name, it->second * map_.Find(register_name)->scale);
}

RigStatus ModbusStage::MoveTo(double mm, double speed_mm_s) {
  // A plain move never stops on force: a limit left armed by an earlier move is cleared.
  RigStatus s = stops_on_force() ? device_->Write("stop_force", 0) : RigStatus{};
  if (s.ok()) s = device_->Write("speed", speed_mm_s);
  if (s.ok()) s = device_->Write("target", mm);
  if (s.ok()) s = device_->Command("command", "move");
  return s;
}

RigStatus ModbusStage::MoveUntilForce(double mm, double speed_mm_s, double stop_n) {
  if (!stops_on_force()) return Stage::MoveUntilForce(mm, speed_mm_s, stop_n);
  RigStatus s = device_->Write("stop_force", stop_n);
  if (s.ok()) s = device_->Write("speed", speed_mm_s);
  if (s.ok()) s = device_->Write("target", mm);
  if (s.ok()) s = device_->Command("command", "move");
  return s;
}

RigStatus ModbusStage::Moving(bool* moving) {
  double v = 0;
  const RigStatus s = device_->Read("moving", &v);
  *moving = v != 0;
  return s;
}

RigStatus ModbusForceSensor::Read(double* newtons) {
  double raw = 0;
  const RigStatus s = device_->Read("force", &raw);
  *newtons = raw - offset_;
  return s;
}

RigStatus ModbusForceSensor::Tare() {
  if (device_->map().Find("tare") != nullptr) {
    offset_ = 0;
    return device_->Command("tare", "tare");
  }
  double raw = 0;
  const RigStatus s = device_->Read("force", &raw);
  if (s.ok()) offset_ = raw;
  return s;
}

}  // namespace palpa::calibration
