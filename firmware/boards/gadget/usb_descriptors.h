// The USB descriptors the gadget presents through FunctionFS: a vendor interface with one bulk IN
// and one bulk OUT endpoint (libusb, `usb:`) and a HID interface with 64-byte input and output
// reports on interrupt endpoints polled every 1 ms (hidapi, `hid:`).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace palpa::gadget {

/// Bytes in a HID report, both directions (no report id).
inline constexpr size_t kHidReportBytes = 64;
/// Full-speed maximum packet size of the bulk endpoints (an MCU's full-speed USB).
inline constexpr size_t kBulkPacketBytes = 64;

/// The HID report descriptor: a vendor-defined usage page, one 64-byte input report and one
/// 64-byte output report.
const std::vector<uint8_t>& HidReportDescriptor();

inline constexpr uint8_t kHidClassDescriptor = 0x21;
inline constexpr uint8_t kHidReportDescriptorType = 0x22;

/// The HID class descriptor (HID 1.11, one report descriptor).
std::vector<uint8_t> HidClassDescriptor();
/// FunctionFS descriptor blob (v2 header, full- and high-speed sets) of the vendor bulk interface.
std::vector<uint8_t> VendorBulkDescriptors();
/// FunctionFS descriptor blob of the HID interface: the HID class descriptor and interrupt IN and
/// OUT endpoints with a 1 ms interval at either speed.
std::vector<uint8_t> HidDescriptors();
/// FunctionFS strings blob with one interface string (US English).
std::vector<uint8_t> InterfaceStrings(const std::string& name);

}  // namespace palpa::gadget
