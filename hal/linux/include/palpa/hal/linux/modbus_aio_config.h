// The configuration of a Modbus analogue I/O module (link, watchdog, channels), read from JSON.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/hal/linux/opened.h"

namespace palpa::hal::linux_aio {

/// The register map of one module class. Only the Beckhoff EK9000 coupler with 0–10 V output
/// (EL4004) and input (EL3064) terminals is known today; docs/linux.md gives its map.
struct ModuleClass {
  const char* name;
  uint16_t outputs_at;        ///< first output word of the process image (FC16, read back FC3)
  uint16_t inputs_at;         ///< first input word of the process image (FC4)
  uint16_t full_scale_code;   ///< the code of 10 V, on outputs and inputs alike
  uint16_t watchdog_time_at;  ///< watchdog time in ms (R/W)
  uint16_t watchdog_type_at;  ///< 0: retriggered by writes only; 1: by any telegram; 2: off
  uint16_t fallback_at;       ///< 0: outputs to zero on a watchdog timeout; 1: freeze; 2: stop
  uint16_t max_channels;      ///< a limit of this driver (one transfer per tick), not the coupler
  uint16_t input_invalid;     ///< status-word bits that make an input's value no reading
};

inline constexpr ModuleClass kBeckhoffEk9000{.name = "beckhoff-ek9000",
                                             .outputs_at = 0x0800,
                                             .inputs_at = 0x0000,
                                             .full_scale_code = 0x7FFF,
                                             .watchdog_time_at = 0x1120,
                                             .watchdog_type_at = 0x1122,
                                             .fallback_at = 0x1123,
                                             .max_channels = 16,
                                             // EL30xx status: bit 6 Error, bit 14 TxPDO State
                                             .input_invalid = 0x4040};

struct ModbusAioConfig {
  const ModuleClass* module = &kBeckhoffEk9000;
  bool tcp = true;
  std::string host = "127.0.0.1";  ///< tcp: address; rtu: serial device
  int port = 502;                  ///< tcp
  int baud = 115200;               ///< rtu
  char parity = 'N';               ///< rtu: N, E or O
  int data_bits = 8, stop_bits = 1;
  int unit = 1;
  int response_timeout_ms = 50;  ///< a module that answers later is an error, never waited for
  int watchdog_ms = 500;         ///< silence after which the module sets its outputs to zero
  uint8_t output_count = 4, output_bits = 12;
  uint8_t input_count = 4, input_bits = 12;
  uint8_t input_words = 2;  ///< words per input channel; the value is the last (status first)

  /// "tcp:HOST:PORT unit N" or "rtu:DEVICE unit N", for messages.
  std::string Describe() const;
};

/// Parses the module's JSON object (docs/linux.md). Every field is checked: an unknown field, a
/// wrong type or a value out of range is refused (kBadValue) naming the field ("module.port: ...").
Opened<ModbusAioConfig> ParseModbusAioConfig(const std::string& json_text);

/// Reads and parses a configuration file; a refusal names the file (kIoError: it cannot be read).
Opened<ModbusAioConfig> LoadModbusAioConfig(const std::string& path);

}  // namespace palpa::hal::linux_aio
