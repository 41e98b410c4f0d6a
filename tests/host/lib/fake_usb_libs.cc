// hidapi and libusb implemented over FakeHid / FakeUsb, linked instead of the real libraries.
#include "fake_usb_libs.h"

#include <hidapi/hidapi.h>
#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <cstring>

namespace palpa::testing {

FakeHid& Hid() {
  static FakeHid hid;
  return hid;
}
FakeUsb& Usb() {
  static FakeUsb usb;
  return usb;
}
void ResetFakes() {
  Hid() = FakeHid{};
  Usb() = FakeUsb{};
}

}  // namespace palpa::testing

using palpa::testing::Hid;
using palpa::testing::Usb;

struct hid_device_ {
  int index;
};
static hid_device_ g_hid_devices[2] = {{0}, {1}};
static char g_hid_path[] = "/dev/hidraw-fake";

/// Notes which handle did what; a handle used both to read and to write is the race the
/// transport must not have (see hid_transport.cc).
static void UseHandle(const hid_device* device, bool write) {
  int& mine = write ? Hid().write_handle : Hid().read_handle;
  const int other = write ? Hid().read_handle : Hid().write_handle;
  mine = device->index;
  if (other == device->index) Hid().mixed_handles = true;
}

extern "C" {

int hid_init(void) { return 0; }
int hid_exit(void) { return 0; }
hid_device_info* hid_enumerate(unsigned short vendor, unsigned short product) {
  if (!Hid().present || vendor != 0x1209 || product != 0x0001) return nullptr;
  auto* info = new hid_device_info{};
  info->path = g_hid_path;
  info->vendor_id = vendor;
  info->product_id = product;
  info->serial_number = Hid().serial.data();
  info->product_string = const_cast<wchar_t*>(Hid().product);
  return info;
}
void hid_free_enumeration(hid_device_info* devices) {
  while (devices != nullptr) {
    hid_device_info* next = devices->next;
    delete devices;
    devices = next;
  }
}
hid_device* hid_open_path(const char* path) {
  if (std::strcmp(path, g_hid_path) != 0 || Hid().opened >= 2 ||
      Hid().opened == Hid().open_failures_after)
    return nullptr;
  return &g_hid_devices[Hid().opened++];
}
void hid_close(hid_device*) {
  ++Hid().closed_handles;
  Hid().closed = Hid().closed_handles == Hid().opened;
}
const wchar_t* hid_error(hid_device*) { return L"fake hidapi error"; }
int hid_read_timeout(hid_device* device, unsigned char* data, size_t length, int) {
  UseHandle(device, false);
  ++Hid().reads;
  if (Hid().disconnected) return -1;
  if (Hid().reports_in.empty()) {
    ++Hid().timeouts;
    return 0;
  }
  const std::vector<uint8_t> r = Hid().reports_in.front();
  Hid().reports_in.erase(Hid().reports_in.begin());
  const size_t n = r.size() < length ? r.size() : length;
  std::memcpy(data, r.data(), n);
  return static_cast<int>(n);
}
int hid_write(hid_device* device, const unsigned char* data, size_t length) {
  UseHandle(device, true);
  if (Hid().disconnected) return -1;
  Hid().reports_out.emplace_back(data, data + length);
  return Hid().short_write_bytes >= 0 ? Hid().short_write_bytes : static_cast<int>(length);
}

static libusb_device* g_usb_devices[2] = {reinterpret_cast<libusb_device*>(0x1), nullptr};
static libusb_device_handle* const g_usb_handle = reinterpret_cast<libusb_device_handle*>(0x2);

int libusb_init(libusb_context** ctx) {
  *ctx = reinterpret_cast<libusb_context*>(0x3);
  return 0;
}
void libusb_exit(libusb_context*) {}
ssize_t libusb_get_device_list(libusb_context*, libusb_device*** list) {
  *list = g_usb_devices;
  return Usb().present ? 1 : 0;
}
void libusb_free_device_list(libusb_device**, int) {}
int libusb_get_device_descriptor(libusb_device*, struct libusb_device_descriptor* d) {
  std::memset(d, 0, sizeof(*d));
  d->idVendor = 0x1209;
  d->idProduct = 0x0001;
  d->iProduct = 2;
  d->iSerialNumber = 3;
  return 0;
}
int libusb_open(libusb_device*, libusb_device_handle** h) {
  if (Usb().access_denied) return LIBUSB_ERROR_ACCESS;
  *h = g_usb_handle;
  return 0;
}
void libusb_close(libusb_device_handle*) {}
int libusb_get_string_descriptor_ascii(libusb_device_handle*, uint8_t index, unsigned char* data,
                                       int length) {
  // As libusb: at most length - 1 characters and a terminating NUL; the count copied returned.
  const char* text = index == 2 ? Usb().product : Usb().serial;
  const size_t n = std::min(std::strlen(text), static_cast<size_t>(length) - 1);
  std::memcpy(data, text, n);
  data[n] = 0;
  return static_cast<int>(n);
}
const char* libusb_error_name(int code) {
  return code == LIBUSB_ERROR_ACCESS ? "LIBUSB_ERROR_ACCESS" : "LIBUSB_ERROR";
}
static libusb_endpoint_descriptor g_endpoints[2];
static libusb_interface_descriptor g_altsetting;
static libusb_interface g_interface;
static libusb_config_descriptor g_config;
int libusb_get_active_config_descriptor(libusb_device*, struct libusb_config_descriptor** config) {
  std::memset(g_endpoints, 0, sizeof(g_endpoints));
  g_endpoints[0].bEndpointAddress = 0x81;
  g_endpoints[0].bmAttributes = LIBUSB_TRANSFER_TYPE_BULK;
  g_endpoints[1].bEndpointAddress = 0x02;
  g_endpoints[1].bmAttributes =
      Usb().has_bulk_pair ? LIBUSB_TRANSFER_TYPE_BULK : LIBUSB_TRANSFER_TYPE_INTERRUPT;
  std::memset(&g_altsetting, 0, sizeof(g_altsetting));
  g_altsetting.bInterfaceNumber = 0;
  g_altsetting.bNumEndpoints = 2;
  g_altsetting.endpoint = g_endpoints;
  g_interface.altsetting = &g_altsetting;
  g_interface.num_altsetting = 1;
  std::memset(&g_config, 0, sizeof(g_config));
  g_config.bNumInterfaces = 1;
  g_config.interface = &g_interface;
  *config = &g_config;
  return 0;
}
void libusb_free_config_descriptor(struct libusb_config_descriptor*) {}
int libusb_claim_interface(libusb_device_handle*, int) { return Usb().claim_result; }
int libusb_release_interface(libusb_device_handle*, int) {
  Usb().released = true;
  return 0;
}
int libusb_clear_halt(libusb_device_handle*, unsigned char) {
  ++Usb().clear_halts;
  return 0;
}
int libusb_bulk_transfer(libusb_device_handle*, unsigned char endpoint, unsigned char* data,
                         int length, int* transferred, unsigned int) {
  *transferred = 0;
  if (Usb().no_device) return LIBUSB_ERROR_NO_DEVICE;
  if (endpoint & LIBUSB_ENDPOINT_IN) {
    if (Usb().stall_next_in > 0) {
      --Usb().stall_next_in;
      return LIBUSB_ERROR_PIPE;
    }
    if (Usb().bulk_in.empty()) return LIBUSB_ERROR_TIMEOUT;
    std::vector<uint8_t>& chunk = Usb().bulk_in.front();
    const int n = static_cast<int>(chunk.size()) < length ? static_cast<int>(chunk.size()) : length;
    std::memcpy(data, chunk.data(), static_cast<size_t>(n));
    chunk.erase(chunk.begin(), chunk.begin() + n);
    if (chunk.empty()) Usb().bulk_in.erase(Usb().bulk_in.begin());
    *transferred = n;
    return 0;
  }
  if (Usb().stall_next_out > 0) {
    --Usb().stall_next_out;
    return LIBUSB_ERROR_PIPE;
  }
  const int n = Usb().out_chunk > 0 && Usb().out_chunk < length ? Usb().out_chunk : length;
  Usb().bulk_out.insert(Usb().bulk_out.end(), data, data + n);
  *transferred = n;
  return 0;
}

}  // extern "C"
