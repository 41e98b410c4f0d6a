// HID and USB transports through link-time fakes of hidapi and libusb: reports and chunking,
// short reads and writes, timeouts, stalls, disconnects and errors.
#include <string>
#include <vector>

#include "fake_usb_libs.h"
#include "palpa/host/device_list.h"
#include "palpa/host/transport.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::testing::Hid;
using palpa::testing::Usb;

TEST_GROUP(HidTransport){void setup() override{palpa::testing::ResetFakes();
}
void teardown() override { palpa::testing::ResetFakes(); }
std::unique_ptr<ph::Transport> Open(const char* uri = "hid:1209:0001") {
  auto t = ph::OpenTransport(uri);
  CHECK_TEXT(t.ok(), t.message.c_str());
  return std::move(t.value);
}
}
;

TEST(HidTransport, WritesReportsWithTheReportIdInFrontAndZeroPadding) {
  auto t = Open();
  std::vector<uint8_t> bytes(100);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i + 1);
  LONGS_EQUAL((int)pp::Status::kOk, (int)t->Write(bytes.data(), bytes.size()));
  LONGS_EQUAL(2, Hid().reports_out.size());
  LONGS_EQUAL(65, Hid().reports_out[0].size());
  LONGS_EQUAL(0, Hid().reports_out[0][0]);  // report id
  LONGS_EQUAL(1, Hid().reports_out[0][1]);
  LONGS_EQUAL(65, Hid().reports_out[1][1]);
  LONGS_EQUAL(0, Hid().reports_out[1][64]);  // padding after the last byte
}

TEST(HidTransport, ReadsReportsShortReportsAndTimeouts) {
  auto t = Open();
  Hid().reports_in.push_back(std::vector<uint8_t>(64, 0x11));
  Hid().reports_in.push_back({0x22, 0x00});  // a short report
  uint8_t buffer[128];
  auto n = t->Read(buffer, sizeof(buffer), 10);
  LONGS_EQUAL(64, n.value);
  n = t->Read(buffer, sizeof(buffer), 10);
  LONGS_EQUAL(2, n.value);
  n = t->Read(buffer, sizeof(buffer), 10);
  CHECK(n.ok());
  LONGS_EQUAL(0, n.value);  // timeout: nothing, not an error
  LONGS_EQUAL(1, Hid().timeouts);
}

TEST(HidTransport, UnplugIsADisconnectAndShortWritesAreErrors) {
  auto t = Open();
  uint8_t b[4] = {1, 2, 3, 0};
  Hid().short_write_bytes = 10;
  LONGS_EQUAL((int)pp::Status::kIoError, (int)t->Write(b, sizeof(b)));
  Hid().disconnected = true;
  LONGS_EQUAL((int)pp::Status::kDisconnected, (int)t->Write(b, sizeof(b)));
  uint8_t buffer[64];
  LONGS_EQUAL((int)pp::Status::kDisconnected, (int)t->Read(buffer, sizeof(buffer), 10).status);
  t.reset();
  CHECK(Hid().closed);
}

TEST(HidTransport, ReadsAndWritesThroughHandlesOfTheirOwn) {
  auto t = Open("hid:1209:0001:ABC");
  LONGS_EQUAL(2, Hid().opened);  // the same node twice: hidapi's error string is per handle
  uint8_t b[4] = {1, 2, 3, 0};
  uint8_t buffer[64];
  Hid().reports_in.push_back({0x22, 0x00});
  for (int i = 0; i < 3; ++i) {
    LONGS_EQUAL((int)pp::Status::kOk, (int)t->Write(b, sizeof(b)));
    CHECK(t->Read(buffer, sizeof(buffer), 10).ok());
  }
  CHECK(Hid().read_handle >= 0 && Hid().write_handle >= 0);
  CHECK_FALSE(Hid().mixed_handles);
  t.reset();
  LONGS_EQUAL(2, Hid().closed_handles);
}

TEST(HidTransport, ASecondHandleThatCannotBeOpenedClosesTheFirst) {
  Hid().open_failures_after = 1;
  std::string error;
  auto t = ph::OpenTransport("hid:1209:0001");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)t.status);
  CHECK(t.message.find("hid:1209:0001: cannot open /dev/hidraw-fake (fake hidapi error)") !=
        std::string::npos);
  LONGS_EQUAL(1, Hid().closed_handles);
}

TEST(HidTransport, OtherSerialNumbersAreNotOpened) {
  auto t = ph::OpenTransport("hid:1209:0001:XYZ");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)t.status);
  CHECK(t.message.find("hid:1209:0001:XYZ: no such device") != std::string::npos);
  LONGS_EQUAL(0, Hid().opened);
}

TEST(HidTransport, MissingDeviceIsNamed) {
  Hid().present = false;
  auto t = ph::OpenTransport("hid:1209:0001:ABC");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)t.status);
  CHECK(t.message.find("hid:1209:0001:ABC") != std::string::npos);
  CHECK(t.message.find("udev") != std::string::npos);
}

TEST_GROUP(UsbTransport){void setup() override{palpa::testing::ResetFakes();
}
void teardown() override { palpa::testing::ResetFakes(); }
}
;

TEST(UsbTransport, BulkInAndOutWithShortTransfersAndStalls) {
  auto t = ph::OpenTransport("usb:1209:0001:PALPA-0042");
  CHECK_TEXT(t.ok(), t.message.c_str());
  Usb().out_chunk = 7;  // the device takes 7 bytes per transfer
  Usb().stall_next_out = 1;
  std::vector<uint8_t> bytes(30, 0xAB);
  LONGS_EQUAL((int)pp::Status::kOk, (int)t.value->Write(bytes.data(), bytes.size()));
  LONGS_EQUAL(30, Usb().bulk_out.size());
  Usb().stall_next_in = 1;
  Usb().bulk_in.push_back({1, 2, 3});
  uint8_t buffer[64];
  auto n = t.value->Read(buffer, sizeof(buffer), 10);
  LONGS_EQUAL(3, n.value);
  LONGS_EQUAL(2, Usb().clear_halts);
  n = t.value->Read(buffer, sizeof(buffer), 10);  // timeout
  CHECK(n.ok());
  LONGS_EQUAL(0, n.value);
  Usb().no_device = true;
  LONGS_EQUAL((int)pp::Status::kDisconnected,
              (int)t.value->Read(buffer, sizeof(buffer), 10).status);
  LONGS_EQUAL((int)pp::Status::kDisconnected, (int)t.value->Write(bytes.data(), 1));
  t.value.reset();
  CHECK(Usb().released);
}

TEST(UsbTransport, OpenFailuresSayWhy) {
  CHECK(ph::OpenTransport("usb:1209:0001:OTHER-SERIAL").status == pp::Status::kNotFound);
  Usb().access_denied = true;
  const auto denied = ph::OpenTransport("usb:1209:0001");
  CHECK(denied.status == pp::Status::kUnavailable);
  CHECK(denied.message.find("udev") != std::string::npos);
  Usb().access_denied = false;
  Usb().has_bulk_pair = false;
  CHECK(ph::OpenTransport("usb:1209:0001").status == pp::Status::kUnsupported);
  Usb().has_bulk_pair = true;
  Usb().claim_result = -6;  // LIBUSB_ERROR_BUSY
  CHECK(ph::OpenTransport("usb:1209:0001").status == pp::Status::kBusy);
  Usb().present = false;
  CHECK(ph::OpenTransport("usb:1209:0001").status == pp::Status::kNotFound);
}

TEST_GROUP(DeviceUri){};

TEST(DeviceUri, BadUrisNameTheirFault) {
  auto opened = ph::OpenTransport("tcp:localhost");
  CHECK(opened.status == pp::Status::kInvalidArgument);
  CHECK(opened.message.find("tcp:HOST:PORT") != std::string::npos);
  CHECK(ph::OpenTransport("tcp:localhost:99999").status == pp::Status::kInvalidArgument);
  opened = ph::OpenTransport("hid:12G9:0001");
  CHECK(opened.status == pp::Status::kInvalidArgument);
  CHECK(opened.message.find("vendor id") != std::string::npos);
  CHECK(ph::OpenTransport("serial:/dev/null?speed=9").status == pp::Status::kInvalidArgument);
  opened = ph::OpenTransport("bluetooth:x");
  CHECK(opened.status == pp::Status::kInvalidArgument);
  CHECK(opened.message.find("unknown scheme") != std::string::npos);
  CHECK(ph::OpenTransport("serial:/nonexistent/tty").status == pp::Status::kNotFound);
  CHECK(ph::OpenTransport("serial:/dev/null").status == pp::Status::kInvalidArgument);  // not a tty
  CHECK(ph::OpenTransport("tcp:127.0.0.1:1").status == pp::Status::kUnavailable);
}

TEST_GROUP(DeviceList){void setup() override{palpa::testing::ResetFakes();
}
void teardown() override { palpa::testing::ResetFakes(); }
}
;

TEST(DeviceList, FindsABoardByItsUsbIdAndProductStringOnHidAndBulk) {
  const auto found = ph::ListDevices();
  std::vector<std::string> boards;
  for (const auto& d : found)
    if (d.palpa) boards.push_back(d.uri + " " + d.product);
  LONGS_EQUAL(2, boards.size());
  STRCMP_EQUAL("hid:1209:0001:ABC palpa actuator board", boards[0].c_str());
  STRCMP_EQUAL("usb:1209:0001:PALPA-0042 palpa actuator board", boards[1].c_str());
}

TEST(DeviceList, ADeviceWithTheSharedTestIdAndAnotherProductIsNotABoard) {
  Hid().product = L"someone's keyboard";
  Usb().product = "a logic analyser";
  for (const auto& d : ph::ListDevices()) {
    if (d.uri.rfind("serial:", 0) == 0) continue;
    CHECK_TEXT(!d.palpa, d.uri.c_str());
    CHECK_TEXT(d.note.find("not a palpa board") != std::string::npos, d.note.c_str());
  }
}

TEST(DeviceList, ADeviceWhoseStringsCannotBeReadSaysWhy) {
  Usb().access_denied = true;
  bool said = false;
  for (const auto& d : ph::ListDevices()) {
    if (d.uri.rfind("usb:", 0) != 0) continue;
    CHECK(!d.palpa);
    said |= d.note.find("udev rule") != std::string::npos;
  }
  CHECK(said);
}
