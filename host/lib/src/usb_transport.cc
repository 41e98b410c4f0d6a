// USB vendor-bulk transport through libusb: one bulk OUT and one bulk IN endpoint.
#include <libusb-1.0/libusb.h>

#include <cstdio>
#include <cstring>

#include "fd_transport.h"

namespace palpa::host {
namespace {

Status FromLibusb(int code) {
  switch (code) {
    case LIBUSB_SUCCESS:
      return Status::kOk;
    case LIBUSB_ERROR_TIMEOUT:
      return Status::kTimeout;
    case LIBUSB_ERROR_NO_DEVICE:
      return Status::kDisconnected;
    case LIBUSB_ERROR_NOT_FOUND:
      return Status::kNotFound;
    case LIBUSB_ERROR_ACCESS:
      return Status::kUnavailable;
    case LIBUSB_ERROR_BUSY:
      return Status::kBusy;
    default:
      return Status::kIoError;
  }
}

class UsbTransport final : public Transport {
 public:
  UsbTransport(libusb_context* context, libusb_device_handle* handle, int interface, uint8_t in,
               uint8_t out, std::string description)
      : context_(context),
        handle_(handle),
        interface_(interface),
        in_(in),
        out_(out),
        description_(std::move(description)) {}
  ~UsbTransport() override {
    libusb_release_interface(handle_, interface_);
    libusb_close(handle_);
    libusb_exit(context_);
  }

  protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    int transferred = 0;
    int rc = libusb_bulk_transfer(handle_, in_, out, static_cast<int>(capacity), &transferred,
                                  static_cast<unsigned>(timeout_ms));
    if (rc == LIBUSB_ERROR_PIPE) {  // the endpoint stalled: clear it once and carry on
      libusb_clear_halt(handle_, in_);
      rc = libusb_bulk_transfer(handle_, in_, out, static_cast<int>(capacity), &transferred,
                                static_cast<unsigned>(timeout_ms));
    }
    if (rc == LIBUSB_SUCCESS || rc == LIBUSB_ERROR_TIMEOUT || rc == LIBUSB_ERROR_OVERFLOW) {
      return static_cast<size_t>(transferred);  // a timeout may still have moved some bytes
    }
    return FromLibusb(rc);
  }

  Status Write(const uint8_t* data, size_t size) override {
    size_t at = 0;
    int stalls = 0;
    while (at < size) {
      int transferred = 0;
      const int rc = libusb_bulk_transfer(handle_, out_, const_cast<uint8_t*>(data + at),
                                          static_cast<int>(size - at), &transferred, 1000);
      at += static_cast<size_t>(transferred);
      if (rc == LIBUSB_ERROR_PIPE && stalls++ == 0) {
        libusb_clear_halt(handle_, out_);
        continue;
      }
      if (rc != LIBUSB_SUCCESS) return FromLibusb(rc);
    }
    return Status::kOk;
  }

  std::string Describe() const override { return description_; }

 private:
  libusb_context* context_;
  libusb_device_handle* handle_;
  int interface_;
  uint8_t in_, out_;
  std::string description_;
};

/// The first interface with both a bulk IN and a bulk OUT endpoint.
bool FindBulkEndpoints(libusb_device* device, int& interface, uint8_t& in, uint8_t& out) {
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(device, &config) != LIBUSB_SUCCESS) return false;
  bool found = false;
  for (int i = 0; i < config->bNumInterfaces && !found; ++i) {
    if (config->interface[i].num_altsetting < 1) continue;
    const libusb_interface_descriptor& d = config->interface[i].altsetting[0];
    uint8_t bulk_in = 0, bulk_out = 0;
    for (int e = 0; e < d.bNumEndpoints; ++e) {
      const libusb_endpoint_descriptor& ep = d.endpoint[e];
      if ((ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) != LIBUSB_TRANSFER_TYPE_BULK) continue;
      if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) {
        bulk_in = ep.bEndpointAddress;
      } else {
        bulk_out = ep.bEndpointAddress;
      }
    }
    if (bulk_in != 0 && bulk_out != 0) {
      interface = d.bInterfaceNumber;
      in = bulk_in;
      out = bulk_out;
      found = true;
    }
  }
  libusb_free_config_descriptor(config);
  return found;
}

}  // namespace

Result<std::unique_ptr<Transport>> OpenUsb(const DeviceUri& uri) {
  char id[16];
  std::snprintf(id, sizeof(id), "%04x:%04x", uri.vendor, uri.product);
  const std::string where =
      "usb:" + std::string(id) + (uri.serial_number.empty() ? "" : ":" + uri.serial_number);
  libusb_context* context = nullptr;
  if (libusb_init(&context) != LIBUSB_SUCCESS) {
    return {Status::kIoError, where + ": libusb failed to initialise"};
  }
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context, &list);
  libusb_device_handle* handle = nullptr;
  int interface = 0;
  uint8_t in = 0, out = 0;
  Status status = Status::kNotFound;
  for (ssize_t i = 0; i < count && handle == nullptr; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != LIBUSB_SUCCESS) continue;
    if (d.idVendor != uri.vendor || d.idProduct != uri.product) continue;
    libusb_device_handle* h = nullptr;
    const int rc = libusb_open(list[i], &h);
    if (rc != LIBUSB_SUCCESS) {
      status = FromLibusb(rc);
      continue;
    }
    if (!uri.serial_number.empty()) {
      unsigned char serial[128] = {0};
      if (d.iSerialNumber == 0 ||
          libusb_get_string_descriptor_ascii(h, d.iSerialNumber, serial, sizeof(serial)) < 0 ||
          uri.serial_number != reinterpret_cast<char*>(serial)) {
        libusb_close(h);
        continue;
      }
    }
    if (!FindBulkEndpoints(list[i], interface, in, out)) {
      libusb_close(h);
      status = Status::kUnsupported;
      continue;
    }
    const int claimed = libusb_claim_interface(h, interface);
    if (claimed != LIBUSB_SUCCESS) {
      libusb_close(h);
      status = FromLibusb(claimed);
      continue;
    }
    handle = h;
  }
  if (count > 0) libusb_free_device_list(list, 1);
  if (handle == nullptr) {
    libusb_exit(context);
    return {status, where + (status == Status::kNotFound ? ": no such device"
                             : status == Status::kUnsupported
                                 ? ": no interface with a bulk IN and a bulk OUT endpoint"
                             : status == Status::kUnavailable
                                 ? ": access denied (install the udev rule, or run as root)"
                                 : std::string(": cannot open: ") + protocol::StatusName(status))};
  }
  return std::unique_ptr<Transport>(new UsbTransport(context, handle, interface, in, out, where));
}

}  // namespace palpa::host
