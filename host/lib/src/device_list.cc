// Board discovery through hidapi, libusb and sysfs (which USB device a tty belongs to).
#include "palpa/host/device_list.h"

#include <dirent.h>
#include <hidapi/hidapi.h>
#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "palpa/host/transport.h"

namespace palpa::host {
namespace {

std::string Narrow(const wchar_t* w) {
  std::string text;
  for (; w != nullptr && *w != L'\0'; ++w) text.push_back(*w < 128 ? static_cast<char>(*w) : '?');
  return text;
}

std::string ReadLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string UsbUri(const char* scheme, const std::string& serial) {
  char id[16];
  std::snprintf(id, sizeof(id), "%04x:%04x", kUsbVendorId, kUsbProductId);
  return std::string(scheme) + ":" + id + (serial.empty() ? "" : ":" + serial);
}

FoundDevice Classified(std::string uri, std::string product, std::string serial) {
  FoundDevice d{std::move(uri), std::move(product), std::move(serial), false, {}};
  d.palpa = IsPalpaBoard(kUsbVendorId, kUsbProductId, d.product);
  if (!d.palpa) {
    d.note = "the shared test id 1209:0001, but the product string '" + d.product +
             "' does not begin with '" + kUsbProductPrefix + "': not a palpa board";
  }
  return d;
}

/// ttyACM* and ttyUSB*, with the USB device each belongs to (from sysfs: the tty's interface,
/// whose parent is the device).
void SerialPorts(std::vector<FoundDevice>& out) {
  std::vector<std::string> names;
  if (DIR* dev = opendir("/dev")) {
    while (dirent* e = readdir(dev)) {
      const std::string name = e->d_name;
      if (name.rfind("ttyACM", 0) == 0 || name.rfind("ttyUSB", 0) == 0) names.push_back(name);
    }
    closedir(dev);
  }
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    FoundDevice d{"serial:/dev/" + name, {}, {}, false, {}};
    // ttyACM: device/ is the USB interface, its parent the device; ttyUSB: one level deeper.
    for (const char* up : {"/device/../", "/device/../../"}) {
      const std::string usb = "/sys/class/tty/" + name + up;
      const std::string vendor = ReadLine(usb + "idVendor"), product = ReadLine(usb + "idProduct");
      if (vendor.empty()) continue;
      d.product = ReadLine(usb + "product");
      d.serial_number = ReadLine(usb + "serial");
      d.palpa = IsPalpaBoard(static_cast<uint16_t>(std::strtoul(vendor.c_str(), nullptr, 16)),
                             static_cast<uint16_t>(std::strtoul(product.c_str(), nullptr, 16)),
                             d.product);
      d.note = "usb " + vendor + ":" + product;
      break;
    }
    out.push_back(d);
  }
}

void HidInterfaces(std::vector<FoundDevice>& out) {
  if (hid_init() != 0) return;
  hid_device_info* list = hid_enumerate(kUsbVendorId, kUsbProductId);
  for (hid_device_info* d = list; d != nullptr; d = d->next) {
    const std::string serial = Narrow(d->serial_number);
    out.push_back(Classified(UsbUri("hid", serial), Narrow(d->product_string), serial));
  }
  hid_free_enumeration(list);
  hid_exit();
}

void BulkInterfaces(std::vector<FoundDevice>& out) {
  libusb_context* context = nullptr;
  if (libusb_init(&context) != 0) return;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0 || d.idVendor != kUsbVendorId ||
        d.idProduct != kUsbProductId) {
      continue;
    }
    libusb_device_handle* h = nullptr;
    const int opened = libusb_open(list[i], &h);
    if (opened != 0) {
      FoundDevice found{UsbUri("usb", ""), {}, {}, false, {}};
      found.note =
          std::string("cannot read its strings: ") + libusb_error_name(opened) +
          (opened == LIBUSB_ERROR_ACCESS ? " (install the udev rule, or run as root)" : "");
      out.push_back(found);
      continue;
    }
    auto text = [h](uint8_t index) {
      unsigned char s[128] = {0};
      return index != 0 && libusb_get_string_descriptor_ascii(h, index, s, sizeof(s)) > 0
                 ? std::string(reinterpret_cast<char*>(s))
                 : std::string();
    };
    const std::string product = text(d.iProduct), serial = text(d.iSerialNumber);
    libusb_close(h);
    out.push_back(Classified(UsbUri("usb", serial), product, serial));
  }
  if (n > 0) libusb_free_device_list(list, 1);
  libusb_exit(context);
}

}  // namespace

bool IsPalpaBoard(uint16_t vendor, uint16_t product, const std::string& product_string) {
  return vendor == kUsbVendorId && product == kUsbProductId &&
         product_string.rfind(kUsbProductPrefix, 0) == 0;
}

std::vector<FoundDevice> ListDevices() {
  std::vector<FoundDevice> found;
  SerialPorts(found);
  HidInterfaces(found);
  BulkInterfaces(found);
  return found;
}

}  // namespace palpa::host
