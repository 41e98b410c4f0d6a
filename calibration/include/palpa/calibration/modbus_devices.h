// A linear stage and a force sensor over Modbus (libmodbus, TCP or RTU), each driven through its
// register map.
#pragma once

#include <memory>
#include <string>

#include "palpa/calibration/register_map.h"
#include "palpa/calibration/rig.h"

typedef struct _modbus modbus_t;

namespace palpa::calibration {

/// One Modbus connection with reads and writes by register name.
class ModbusDevice {
 public:
  /// Connects; unavailable when the address cannot be reached.
  static host::Result<std::unique_ptr<ModbusDevice>> Open(const RegisterMap& map);
  ~ModbusDevice();
  RigStatus Read(const std::string& name, double* value);
  RigStatus Write(const std::string& name, double value);
  RigStatus Command(const char* register_name, const char* command);
  const RegisterMap& map() const { return map_; }

 private:
  ModbusDevice(const RegisterMap& map, modbus_t* ctx) : map_(map), ctx_(ctx) {}
  RigStatus Failure(const std::string& what);
  RegisterMap map_;
  modbus_t* ctx_;
};

class ModbusStage final : public Stage {
 public:
  explicit ModbusStage(std::unique_ptr<ModbusDevice> device) : device_(std::move(device)) {}
  RigStatus MoveTo(double mm, double speed_mm_s) override;
  RigStatus Position(double* mm) override { return device_->Read("position", mm); }
  RigStatus Moving(bool* moving) override;
  RigStatus Stop() override { return device_->Command("command", "stop"); }
  /// With a "stop_force" register (N; 0 disarms it) the controller stops a move on its load cell.
  bool stops_on_force() const override { return device_->map().Find("stop_force") != nullptr; }
  RigStatus MoveUntilForce(double mm, double speed_mm_s, double stop_n) override;

 private:
  std::unique_ptr<ModbusDevice> device_;
};

/// Tares through the device's tare register when it has one, otherwise by remembering an offset.
class ModbusForceSensor final : public ForceSensor {
 public:
  explicit ModbusForceSensor(std::unique_ptr<ModbusDevice> device) : device_(std::move(device)) {}
  RigStatus Read(double* newtons) override;
  RigStatus Tare() override;

 private:
  std::unique_ptr<ModbusDevice> device_;
  double offset_ = 0;
};

}  // namespace palpa::calibration
