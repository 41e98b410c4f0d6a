// Device URI parsing.
#include "palpa/host/device_uri.h"

#include <cstdlib>

#include "palpa/core/board_configs.h"

namespace palpa::host {
namespace {

using protocol::Status;

Result<DeviceUri> Fail(const std::string& uri, const std::string& what) {
  return {Status::kInvalidArgument, "device '" + uri + "': " + what};
}

bool Hex16(const std::string& text, uint16_t& out) {
  if (text.empty() || text.size() > 4) return false;
  char* end = nullptr;
  const unsigned long v = std::strtoul(text.c_str(), &end, 16);
  if (*end != '\0') return false;
  out = static_cast<uint16_t>(v);
  return true;
}

}  // namespace

Result<DeviceUri> ParseDeviceUri(const std::string& uri) {
  const size_t colon = uri.find(':');
  const std::string scheme = uri.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "" : uri.substr(colon + 1);
  DeviceUri out;
  if (scheme == "sim") {
    out.kind = DeviceUri::Kind::kSim;
    if (!rest.empty()) out.config = rest;
    return out;
  }
  if (scheme == "serial") {
    out.kind = DeviceUri::Kind::kSerial;
    const size_t q = rest.find('?');
    out.path = rest.substr(0, q);
    if (out.path.empty()) return Fail(uri, "expected serial:PATH[?baud=N]");
    if (q != std::string::npos) {
      const std::string query = rest.substr(q + 1);
      if (query.rfind("baud=", 0) != 0)
        return Fail(uri, "unknown option '" + query + "' (expected baud=N)");
      char* end = nullptr;
      const long baud = std::strtol(query.c_str() + 5, &end, 10);
      if (*end != '\0' || baud <= 0) return Fail(uri, "baud must be a positive number");
      out.baud = static_cast<uint32_t>(baud);
    }
    return out;
  }
  if (scheme == "tcp") {
    out.kind = DeviceUri::Kind::kTcp;
    const size_t c = rest.rfind(':');
    if (c == std::string::npos || c == 0) return Fail(uri, "expected tcp:HOST:PORT");
    out.host = rest.substr(0, c);
    char* end = nullptr;
    const long port = std::strtol(rest.c_str() + c + 1, &end, 10);
    if (*end != '\0' || port <= 0 || port > 65535 || c + 1 == rest.size()) {
      return Fail(uri, "the port must be a number from 1 to 65535");
    }
    out.port = static_cast<uint16_t>(port);
    return out;
  }
  if (scheme == "hid" || scheme == "usb") {
    out.kind = scheme == "hid" ? DeviceUri::Kind::kHid : DeviceUri::Kind::kUsb;
    const size_t c1 = rest.find(':');
    const size_t c2 = c1 == std::string::npos ? std::string::npos : rest.find(':', c1 + 1);
    if (c1 == std::string::npos)
      return Fail(uri, "expected " + scheme + ":VID:PID[:SERIAL] (hex ids)");
    if (!Hex16(rest.substr(0, c1), out.vendor))
      return Fail(uri, "vendor id '" + rest.substr(0, c1) + "' is not 1-4 hex digits");
    const std::string pid =
        rest.substr(c1 + 1, c2 == std::string::npos ? std::string::npos : c2 - c1 - 1);
    if (!Hex16(pid, out.product))
      return Fail(uri, "product id '" + pid + "' is not 1-4 hex digits");
    if (c2 != std::string::npos) out.serial_number = rest.substr(c2 + 1);
    return out;
  }
  return Fail(uri, "unknown scheme '" + scheme + "' (expected sim, serial, tcp, hid or usb)");
}

std::string SimConfigError(const std::string& config) {
  if (core::FindBoardConfig(config.c_str()) != nullptr) return "";
  std::string known;
  for (uint8_t k = 0; k < core::kBoardConfigCount; ++k)
    known += std::string(k ? ", " : "") + core::kBoardConfigs[k].name;
  return "unknown configuration (" + known + ")";
}

}  // namespace palpa::host
