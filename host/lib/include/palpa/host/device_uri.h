// Parsing of device URIs, with an error that says which part is wrong.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/host/outcome.h"

namespace palpa::host {

struct DeviceUri {
  enum class Kind { kSim, kSerial, kTcp, kHid, kUsb } kind = Kind::kSim;
  std::string config = "thesis-5finger";  ///< sim
  std::string path;                       ///< serial
  uint32_t baud = 1000000;                ///< serial
  std::string host;                       ///< tcp
  uint16_t port = 0;                      ///< tcp
  uint16_t vendor = 0, product = 0;       ///< hid, usb
  std::string serial_number;              ///< hid, usb (optional)
};

/// sim:CONFIG, serial:PATH[?baud=N], tcp:HOST:PORT, hid:VID:PID[:SERIAL], usb:VID:PID[:SERIAL];
/// an invalid argument naming the part that is wrong ("device 'tcp:x': expected tcp:HOST:PORT").
Result<DeviceUri> ParseDeviceUri(const std::string& uri);

/// Empty when palpa-sim knows the board configuration `config` (sim:CONFIG); else
/// "unknown configuration (thesis-pneumatic-3, ...)", naming those it knows.
std::string SimConfigError(const std::string& config);

}  // namespace palpa::host
