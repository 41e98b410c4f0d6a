// USB HID transport through hidapi: the byte stream in 64-byte reports, report id in front.
#include <hidapi/hidapi.h>

#include <cstring>
#include <cwchar>
#include <vector>

#include "fd_transport.h"

namespace palpa::host {
namespace {

constexpr size_t kReportBytes = 64;

/// hidapi's last error outside any handle (opening).
std::string HidGlobalError() {
  const wchar_t* w = hid_error(nullptr);
  if (w == nullptr) return "unknown error";
  std::string text;
  for (; *w != L'\0'; ++w) text.push_back(*w < 128 ? static_cast<char>(*w) : '?');
  return text;
}

// Two handles on one device node: the link reads on its reader thread and writes on the callers'
// threads. hidapi keeps a handle's last error in the handle, and on the hidraw backend both
// hid_read_timeout and hid_write replace it (free, then store) without a lock, so a reader and a
// writer sharing a handle race on that string: after a failed write both can free it. Separate
// handles share nothing. hidraw gives each open file its own copy of every input report; the
// write handle's copies, never read, stay in the kernel's bounded per-file queue (new reports are
// dropped there when it is full).
class HidTransport final : public Transport {
 public:
  HidTransport(hid_device* reader, hid_device* writer, std::string description)
      : reader_(reader), writer_(writer), description_(std::move(description)) {}
  ~HidTransport() override {
    hid_close(reader_);
    hid_close(writer_);
    hid_exit();
  }

  protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    uint8_t report[kReportBytes];
    const int n = hid_read_timeout(reader_, report, sizeof(report), timeout_ms);
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
      const int n = hid_write(writer_, report, sizeof(report));
      if (n < 0) return Status::kDisconnected;
      if (static_cast<size_t>(n) < sizeof(report))
        return Status::kIoError;  // a short write loses a report
    }
    return Status::kOk;
  }

  std::string Describe() const override { return description_; }

 private:
  hid_device* reader_;  ///< the link's reader thread only
  hid_device* writer_;  ///< writers, which the link serialises
  std::string description_;
};

/// The device node of the first HID interface with this vendor, product and (if given) serial
/// number, as hid_open would choose it; empty when there is none.
std::string FindDevicePath(uint16_t vendor, uint16_t product, const std::wstring& serial) {
  std::string path;
  hid_device_info* devices = hid_enumerate(vendor, product);
  for (const hid_device_info* d = devices; d != nullptr; d = d->next) {
    if (d->path == nullptr) continue;
    if (serial.empty() || (d->serial_number != nullptr && serial == d->serial_number)) {
      path = d->path;
      break;
    }
  }
  hid_free_enumeration(devices);
  return path;
}

}  // namespace

Result<std::unique_ptr<Transport>> OpenHid(const DeviceUri& uri) {
  char id[16];
  std::snprintf(id, sizeof(id), "%04x:%04x", uri.vendor, uri.product);
  const std::string where =
      "hid:" + std::string(id) + (uri.serial_number.empty() ? "" : ":" + uri.serial_number);
  if (hid_init() != 0) {
    return {Status::kIoError, where + ": hidapi failed to initialise"};
  }
  const std::wstring serial(uri.serial_number.begin(), uri.serial_number.end());
  const std::string path = FindDevicePath(uri.vendor, uri.product, serial);
  if (path.empty()) {
    hid_exit();
    return {Status::kNotFound,
            where + ": no such device; is it plugged in, and does the udev rule give you access?"};
  }
  hid_device* reader = hid_open_path(path.c_str());
  hid_device* writer = reader != nullptr ? hid_open_path(path.c_str()) : nullptr;
  if (writer == nullptr) {
    const std::string why = where + ": cannot open " + path + " (" + HidGlobalError() +
                            "); does the udev rule give you access?";
    if (reader != nullptr) hid_close(reader);
    hid_exit();
    return {Status::kNotFound, why};
  }
  return std::unique_ptr<Transport>(new HidTransport(reader, writer, where));
}

}  // namespace palpa::host
