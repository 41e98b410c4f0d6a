// FunctionFS descriptor and string blobs, little-endian field by field as the kernel reads them.
#include "usb_descriptors.h"

#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>

namespace palpa::gadget {
namespace {

void Put16(std::vector<uint8_t>& out, uint16_t v) {
  out.push_back(static_cast<uint8_t>(v));
  out.push_back(static_cast<uint8_t>(v >> 8));
}

void Put32(std::vector<uint8_t>& out, uint32_t v) {
  Put16(out, static_cast<uint16_t>(v));
  Put16(out, static_cast<uint16_t>(v >> 16));
}

void Interface(std::vector<uint8_t>& out, uint8_t endpoints, uint8_t interface_class) {
  out.insert(out.end(), {USB_DT_INTERFACE_SIZE, USB_DT_INTERFACE, 0, 0, endpoints, interface_class,
                         0, 0, 1});  // iInterface: the function's first string
}

void Endpoint(std::vector<uint8_t>& out, uint8_t address, uint8_t type, uint16_t packet,
              uint8_t interval) {
  out.insert(out.end(), {USB_DT_ENDPOINT_SIZE, USB_DT_ENDPOINT, address, type});
  Put16(out, packet);
  out.push_back(interval);
}

void HidClass(std::vector<uint8_t>& out) {
  const std::vector<uint8_t> hid = HidClassDescriptor();
  out.insert(out.end(), hid.begin(), hid.end());
}

/// v2 header (magic, length, flags, one count per speed), then the full- and high-speed sets.
std::vector<uint8_t> Blob(const std::vector<uint8_t>& fs, uint32_t fs_count,
                          const std::vector<uint8_t>& hs, uint32_t hs_count) {
  std::vector<uint8_t> out;
  Put32(out, FUNCTIONFS_DESCRIPTORS_MAGIC_V2);
  Put32(out, static_cast<uint32_t>(5 * 4 + fs.size() + hs.size()));
  Put32(out, FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC);
  Put32(out, fs_count);
  Put32(out, hs_count);
  out.insert(out.end(), fs.begin(), fs.end());
  out.insert(out.end(), hs.begin(), hs.end());
  return out;
}

}  // namespace

const std::vector<uint8_t>& HidReportDescriptor() {
  static const std::vector<uint8_t> descriptor = {
      0x06, 0x00, 0xFF,  // usage page: vendor defined 0xFF00
      0x09, 0x01,        // usage 1
      0xA1, 0x01,        // collection: application
      0x15, 0x00,        //   logical minimum 0
      0x26, 0xFF, 0x00,  //   logical maximum 255
      0x75, 0x08,        //   report size: 8 bits
      0x95, 0x40,        //   report count: 64
      0x09, 0x01,        //   usage 1
      0x81, 0x02,        //   input: data, variable, absolute
      0x95, 0x40,        //   report count: 64
      0x09, 0x01,        //   usage 1
      0x91, 0x02,        //   output: data, variable, absolute
      0xC0,              // end collection
  };
  return descriptor;
}

std::vector<uint8_t> HidClassDescriptor() {
  std::vector<uint8_t> out{9, kHidClassDescriptor};
  Put16(out, 0x0111);  // bcdHID 1.11
  out.insert(out.end(), {0, 1, kHidReportDescriptorType});
  Put16(out, static_cast<uint16_t>(HidReportDescriptor().size()));
  return out;
}

std::vector<uint8_t> VendorBulkDescriptors() {
  std::vector<uint8_t> fs, hs;
  Interface(fs, 2, USB_CLASS_VENDOR_SPEC);
  Endpoint(fs, 1 | USB_DIR_IN, USB_ENDPOINT_XFER_BULK, kBulkPacketBytes, 0);
  Endpoint(fs, 2 | USB_DIR_OUT, USB_ENDPOINT_XFER_BULK, kBulkPacketBytes, 0);
  Interface(hs, 2, USB_CLASS_VENDOR_SPEC);
  Endpoint(hs, 1 | USB_DIR_IN, USB_ENDPOINT_XFER_BULK, 512, 0);
  Endpoint(hs, 2 | USB_DIR_OUT, USB_ENDPOINT_XFER_BULK, 512, 0);
  return Blob(fs, 3, hs, 3);
}

std::vector<uint8_t> HidDescriptors() {
  std::vector<uint8_t> fs, hs;
  // Full speed counts bInterval in 1 ms frames; high speed as 2^(n-1) 125 µs microframes.
  Interface(fs, 2, USB_CLASS_HID);
  HidClass(fs);
  Endpoint(fs, 1 | USB_DIR_IN, USB_ENDPOINT_XFER_INT, kHidReportBytes, 1);
  Endpoint(fs, 2 | USB_DIR_OUT, USB_ENDPOINT_XFER_INT, kHidReportBytes, 1);
  Interface(hs, 2, USB_CLASS_HID);
  HidClass(hs);
  Endpoint(hs, 1 | USB_DIR_IN, USB_ENDPOINT_XFER_INT, kHidReportBytes, 4);
  Endpoint(hs, 2 | USB_DIR_OUT, USB_ENDPOINT_XFER_INT, kHidReportBytes, 4);
  return Blob(fs, 4, hs, 4);
}

std::vector<uint8_t> InterfaceStrings(const std::string& name) {
  std::vector<uint8_t> out;
  Put32(out, FUNCTIONFS_STRINGS_MAGIC);
  Put32(out, static_cast<uint32_t>(16 + 2 + name.size() + 1));
  Put32(out, 1);  // strings per language
  Put32(out, 1);  // languages
  Put16(out, 0x0409);
  out.insert(out.end(), name.begin(), name.end());
  out.push_back(0);
  return out;
}

}  // namespace palpa::gadget
