// Finding boards: USB devices with palpa's id and product string, on each interface a host
// reaches them by (HID, vendor bulk, the CDC-ACM serial port), and serial ports.
#pragma once

#include <string>
#include <vector>

namespace palpa::host {

/// What every palpa board's USB product string begins with. The USB id (1209:0001, the pid.codes
/// test id) is shared with other hobby devices: the product string tells a palpa board apart.
inline constexpr char kUsbProductPrefix[] = "palpa";

struct FoundDevice {
  std::string uri;            ///< "usb:1209:0001:SERIAL", "hid:1209:0001:SERIAL", "serial:/dev/..."
  std::string product;        ///< the USB product string (empty: not USB, or not readable)
  std::string serial_number;  ///< the USB serial number string
  bool palpa = false;         ///< palpa's USB id and product string
  std::string note;           ///< why it is not taken for a board, or what could not be read
};

/// Serial ports (ttyACM*, ttyUSB*) and the HID and vendor-bulk interfaces of USB devices with
/// palpa's id. Devices with the id but another product string are listed with palpa = false.
std::vector<FoundDevice> ListDevices();

/// True for palpa's USB id and a product string beginning with kUsbProductPrefix.
bool IsPalpaBoard(uint16_t vendor, uint16_t product, const std::string& product_string);

}  // namespace palpa::host
