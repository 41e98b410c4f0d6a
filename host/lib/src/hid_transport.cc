// USB HID transport through hidapi: the byte stream in 64-byte reports, report id in front.
#include <hidapi/hidapi.h>

#include <cstring>
#include <cwchar>
#include <vector>

#include "fd_transport.h"

namespace palpa::host {
namespace {

constexpr size_t kReportBytes = 64;

std::string HidError(hid_device* device) {
  const wchar_t* w = hid_error(device);
  if (w == nullptr) return "unknown error";
  std::string text;
  for (; *w != L'\0'; ++w) text.push_back(*w < 128 ? static_cast<char>(*w) : '?');
  return text;
}

class HidTransport final : public Transport {
 public:
  HidTransport(hid_device* device, std::string description)
      : device_(device), description_(std::move(description)) {}
  ~HidTransport() override {
    hid_close(device_);
    hid_exit();
  }

  Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    uint8_t report[kReportBytes];
    const int n = hid_read_timeout(device_, report, sizeof(report), timeout_ms);
    if (n < 0) return Status::kDisconnected;  // hidapi reports an unplugged device as a read error
    // Zero padding after the last delimiter reads as empty frames: hand it on as it is.
    const size_t count = static_cast<size_t>(n) < capacity ? static_cast<size_t>(n) : capacity;
    std::memcpy(out, report, count);
    return count;
  }

  Status Write(const uint8_t* data, size_t size) override {
    for (size_t at = 0; at < size; at += kReportBytes) {
      uint8_t report[kReportBytes + 1] = {0};  // report id 0, then the payload, zero padded
      const size_t chunk = size - at < kReportBytes ? size - at : kReportBytes;
      std::memcpy(report + 1, data + at, chunk);
      const int n = hid_write(device_, report, sizeof(report));
      if (n < 0) return Status::kDisconnected;
      if (static_cast<size_t>(n) < sizeof(report))
        return Status::kIoError;  // a short write loses a report
    }
    return Status::kOk;
  }

  std::string Describe() const override { return description_; }

 private:
  hid_device* device_;
  std::string description_;
};

}  // namespace

Result<std::unique_ptr<Transport>> OpenHid(const DeviceUri& uri, std::string* error) {
  char id[16];
  std::snprintf(id, sizeof(id), "%04x:%04x", uri.vendor, uri.product);
  const std::string where =
      "hid:" + std::string(id) + (uri.serial_number.empty() ? "" : ":" + uri.serial_number);
  if (hid_init() != 0) {
    *error = where + ": hidapi failed to initialise";
    return Status::kIoError;
  }
  std::wstring serial(uri.serial_number.begin(), uri.serial_number.end());
  hid_device* device = hid_open(uri.vendor, uri.product, serial.empty() ? nullptr : serial.c_str());
  if (device == nullptr) {
    *error = where + ": no such device (" + HidError(nullptr) +
             "); is it plugged in, and does the udev rule give you access?";
    hid_exit();
    return Status::kNotFound;
  }
  return std::unique_ptr<Transport>(new HidTransport(device, where));
}

}  // namespace palpa::host
