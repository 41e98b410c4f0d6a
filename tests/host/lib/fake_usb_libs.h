// Link-time fakes of hidapi and libusb: scriptable devices for the HID and USB transports.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace palpa::testing {

struct FakeHid {
  bool present = true;
  std::wstring serial = L"ABC";                      ///< the one device's serial number
  const wchar_t* product = L"palpa actuator board";  ///< literals: no allocation in a test
  int open_failures_after = -1;  ///< >=0: hid_open_path fails once that many opens succeeded
  int opened = 0, closed_handles = 0;
  int read_handle = -1, write_handle = -1;  ///< which handle (0, 1: order opened) last read, wrote
  bool mixed_handles = false;               ///< a read and a write went through the same handle
  bool disconnected = false;                ///< hid_read/hid_write fail as after an unplug
  int short_write_bytes = -1;               ///< >=0: hid_write reports that many bytes
  std::vector<std::vector<uint8_t>> reports_in;   ///< what hid_read returns, one report per call
  std::vector<std::vector<uint8_t>> reports_out;  ///< what hid_write got
  int reads = 0, timeouts = 0;
  bool closed = false;
};

struct FakeUsb {
  bool present = true;
  bool access_denied = false;
  const char* product = "palpa actuator board";  ///< string descriptor 2
  const char* serial = "PALPA-0042";             ///< string descriptor 3
  bool has_bulk_pair = true;
  int claim_result = 0;
  std::vector<std::vector<uint8_t>> bulk_in;  ///< chunks returned by IN transfers
  std::vector<uint8_t> bulk_out;              ///< everything OUT transfers took
  int stall_next_in = 0;                      ///< IN transfers to fail with PIPE
  int stall_next_out = 0;
  int out_chunk = 0;  ///< >0: OUT transfers move at most this many bytes
  bool no_device = false;
  int clear_halts = 0;
  bool released = false;
};

FakeHid& Hid();
FakeUsb& Usb();
void ResetFakes();

}  // namespace palpa::testing
