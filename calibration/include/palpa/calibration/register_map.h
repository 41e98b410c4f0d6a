// A Modbus device described by data: its address and a register map (table, address, type,
// scale, byte and word order), so a lab points palpa at its own load-cell amplifier and stage
// controller without code. Parsing validates every field and names the one that is wrong.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/outcome.h"

namespace palpa::calibration {

enum class RegisterTable { kHolding, kInput };
enum class RegisterType { kU16, kI16, kU32, kI32, kF32 };

struct Register {
  RegisterTable table = RegisterTable::kHolding;
  int address = 0;
  RegisterType type = RegisterType::kU16;
  double scale = 1;  ///< value = raw · scale
  std::string unit;
  int words() const { return type == RegisterType::kU16 || type == RegisterType::kI16 ? 1 : 2; }
};

/// Where a Modbus device is: modbus-tcp://HOST:PORT/UNIT or modbus-rtu:/dev/ttyX?baud=N&unit=U.
struct ModbusAddress {
  bool tcp = true;
  std::string host;  ///< or the serial device path
  int port = 502;
  int baud = 115200;
  int unit = 1;
};
/// An invalid argument saying what is wrong with the address.
host::Result<ModbusAddress> ParseModbusAddress(const std::string& uri);

struct RegisterMap {
  ModbusAddress address;
  std::string uri;
  bool byte_swap = false;       ///< bytes within a register little-endian (Modbus: big)
  bool low_word_first = false;  ///< 32-bit values: low register first
  int timeout_ms = 500;
  std::map<std::string, Register> registers;
  std::map<std::string, int> commands;  ///< values written to the "command" / "tare" registers

  const Register* Find(const std::string& name) const;
  /// Encodes a value into its registers, and back.
  std::vector<uint16_t> Encode(const Register& r, double value) const;
  double Decode(const Register& r, const uint16_t* words) const;
};

/// `required`: register names the device kind needs. Errors (invalid argument) name the JSON
/// path (prefix first).
host::Result<RegisterMap> ParseRegisterMap(const nlohmann::json& j, const std::string& path,
                                           const std::vector<std::string>& required);

/// Register names each kind needs.
extern const std::vector<std::string>
    kStageRegisters;  ///< position, target, speed, command, moving
extern const std::vector<std::string> kForceRegisters;  ///< force (tare optional)

}  // namespace palpa::calibration
