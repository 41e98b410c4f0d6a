// Runs inside the real-kernel guest, on the host side of dummy_hcd: the host library reaches a
// palpa-sim through palpa-gadget over the kernel's USB stack — vendor bulk through libusb (usb:),
// HID through hidapi and hidraw (hid:), CDC-ACM through a tty (serial:) — and is held to the same
// behaviour as every other board. The gadget is unbound and bound again as a cable is pulled; a
// session is closed on purpose.
//   PALPA_GADGET_CONFIGFS  the gadget's configfs directory (its UDC attribute binds it)
//   PALPA_GADGET_UDC       the controller it is bound to
//   PALPA_GADGET_TTY       the host's tty for its ACM function (default /dev/ttyACM0)
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "board_behaviour.h"
#include "palpa/host/device.h"
#include "palpa/host/device_list.h"
#include "palpa/host/fault_text.h"
#include "palpa/protocol/faults.h"
#include "wait_until.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
namespace pt = palpa::testing;

namespace {

std::string Env(const char* name, const char* fallback = "") {
  const char* value = std::getenv(name);
  return value != nullptr ? value : fallback;
}

std::string SerialUri() { return "serial:" + Env("PALPA_GADGET_TTY", "/dev/ttyACM0"); }

/// Binds the gadget to its controller (plugged in) or unbinds it (unplugged).
void Plug(bool in) {
  const std::string path = Env("PALPA_GADGET_CONFIGFS") + "/UDC";
  const std::string value = in ? Env("PALPA_GADGET_UDC") : std::string("\n");
  const int fd = open(path.c_str(), O_WRONLY);
  CHECK_TEXT(fd >= 0, ("cannot open " + path + " (is PALPA_GADGET_CONFIGFS set?)").c_str());
  const bool written = write(fd, value.data(), value.size()) == static_cast<ssize_t>(value.size());
  close(fd);
  CHECK_TEXT(written, ("cannot write " + path).c_str());
}

std::string Events(ph::Device& d) {
  std::string all;
  for (const std::string& e : d.link().TakeEvents()) all += e + "\n";
  return all;
}

/// Holds line 1 at `kpa` and waits for the plant to get there.
void HoldLine(ph::Device& d, double kpa) {
  const ph::Outcome set = d.SetLines({{0, kpa}});
  CHECK_TEXT(set.ok(), set.message.c_str());
  std::atomic<int32_t> measured{0};
  std::atomic<uint32_t> faults{0};
  std::atomic<uint8_t> status{0};
  const int id = d.Subscribe([&](const ph::TelemetryFrame& f) {
    const pp::LineSample& s =
        f.telemetry.samples[(f.telemetry.tick_count - 1) * f.telemetry.line_count];
    measured = s.measured_pa;
    status = s.status;
    faults = f.telemetry.fault_bitmap;
  });
  const int32_t target = static_cast<int32_t>(kpa * 1000);
  const bool reached = pt::WaitUntil([&] { return std::abs(measured.load() - target) < 1000; }, 4);
  d.Unsubscribe(id);
  CHECK_TEXT(reached, ("line 1 at " + std::to_string(measured.load()) + " Pa, status 0x" +
                       std::to_string(status.load()) + ", faults " + ph::FaultNames(faults.load()))
                          .c_str());
}

/// Pulls the cable with a line actuated and plugs it back in: the library reports the loss,
/// refuses commands while the board is gone, reopens it and opens a new session; the board went
/// safe on host silence meanwhile and takes setpoints again once the fault is cleared.
void CheckUnplugAndReplug(const std::string& uri) {
  auto opened = ph::Device::Open(uri, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  d.ClearFault();
  HoldLine(d, 30.0);
  Events(d);

  Plug(false);
  CHECK_TEXT(pt::WaitUntil([&] { return !d.link().session_open(); }, 5), "the loss went unnoticed");
  const std::string lost = Events(d);
  CHECK_TEXT(lost.find("was lost") != std::string::npos, lost.c_str());
  const ph::Outcome refused = d.SetLines({{0, 20.0}});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)refused.status);

  Plug(true);
  CHECK_TEXT(pt::WaitUntil([&] { return d.link().session_open(); }, 30), "not reopened");
  const std::string back = Events(d);
  CHECK_TEXT(back.find("reopened " + uri) != std::string::npos, back.c_str());
  CHECK(d.link().counters().reopens >= 1);

  const auto diagnostics = d.Diagnostics();
  CHECK_TEXT(diagnostics.ok(), diagnostics.message.c_str());
  CHECK_TEXT((diagnostics.value.fault_bitmap & pp::FaultBit(pp::Fault::kHostSilence)) != 0,
             ph::FaultNames(diagnostics.value.fault_bitmap).c_str());
  CHECK(d.ClearFault().ok());
  HoldLine(d, 20.0);
}

/// Closes a session with a line actuated: later commands of that session get no_session, the next
/// host opens the board at once (it is not busy) and finds every line safe with nothing latched,
/// and still nothing three host-silence timeouts later (a session left to fall silent with a line
/// actuated would have latched host_silence).
void CheckCloseEndsTheSessionWithoutAFault(const std::string& uri) {
  auto opened = ph::Device::Open(uri, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  CHECK(d.ClearFault().ok());
  HoldLine(d, 30.0);
  const uint32_t timeout_us = d.info().host_timeout_us;
  const ph::Outcome closed = d.Close();
  CHECK_TEXT(closed.ok(), closed.message.c_str());
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)d.SetLines({{0, 20.0}}).status);
  opened.value.reset();  // the interface released (libusb lets one handle claim it)

  auto next = ph::Device::Open(uri, {});
  CHECK_TEXT(next.ok(), next.message.c_str());
  auto faults = [&] {
    const auto diagnostics = next.value->Diagnostics();
    CHECK_TEXT(diagnostics.ok(), diagnostics.message.c_str());
    return diagnostics.value.fault_bitmap;
  };
  CHECK_TEXT(faults() == 0, ph::FaultNames(faults()).c_str());
  std::atomic<int> safe_lines{-1};
  const int id = next.value->Subscribe([&](const ph::TelemetryFrame& f) {
    const pp::Telemetry& t = f.telemetry;
    int safe = 0;
    for (uint8_t i = 0; i < t.line_count; ++i)
      safe +=
          (t.samples[(t.tick_count - 1) * t.line_count + i].status & pp::line_status::kSafe) != 0;
    safe_lines = safe == t.line_count ? 1 : 0;
  });
  CHECK_TEXT(pt::WaitUntil([&] { return safe_lines.load() >= 0; }, 4), "no telemetry");
  next.value->Unsubscribe(id);
  LONGS_EQUAL(1, safe_lines.load());
  std::this_thread::sleep_for(std::chrono::microseconds(3 * timeout_us));
  CHECK_TEXT(faults() == 0, ph::FaultNames(faults()).c_str());
}

/// Sets the board's telemetry decimation (over vendor bulk, which has room for anything).
void SetTelemetryDecimation(uint16_t every) {
  auto opened = ph::Device::Open("usb:1209:0001", {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  auto board = opened.value->ReadBoard();
  CHECK_TEXT(board.ok(), board.message.c_str());
  board.value.telemetry_decimation = every;
  const ph::Outcome configured = opened.value->ConfigureBoard(board.value);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
}

}  // namespace

TEST_GROUP(GadgetBulk){};

TEST(GadgetBulk, BehavesAsTheProtocolSays) {
  palpa::testing::CheckBoardBehaviour("usb:1209:0001", pp::BoardKind::kSim);
}

TEST(GadgetBulk, UnpluggedAndPluggedBackIn) { CheckUnplugAndReplug("usb:1209:0001"); }

TEST(GadgetBulk, CloseEndsTheSessionWithoutAFault) {
  CheckCloseEndsTheSessionWithoutAFault("usb:1209:0001");
}

// HID carries 64 bytes a millisecond: thesis-5finger's 7 lines at every tick would need 155 % of
// it, so the board sends a sample every 4 ticks, as the budget in docs/protocol.md says.
TEST_GROUP(GadgetHid){void setup() override{SetTelemetryDecimation(4);
}
void teardown() override { SetTelemetryDecimation(1); }
}
;

TEST(GadgetHid, BehavesAsTheProtocolSays) {
  palpa::testing::CheckBoardBehaviour("hid:1209:0001", pp::BoardKind::kSim);
}

TEST(GadgetHid, UnpluggedAndPluggedBackIn) { CheckUnplugAndReplug("hid:1209:0001"); }

TEST(GadgetHid, CloseEndsTheSessionWithoutAFault) {
  CheckCloseEndsTheSessionWithoutAFault("hid:1209:0001");
}

TEST_GROUP(GadgetAcm){};

TEST(GadgetAcm, BehavesAsTheProtocolSays) {
  palpa::testing::CheckBoardBehaviour(SerialUri(), pp::BoardKind::kSim);
}

TEST(GadgetAcm, UnpluggedAndPluggedBackIn) { CheckUnplugAndReplug(SerialUri()); }

TEST(GadgetAcm, CloseEndsTheSessionWithoutAFault) {
  CheckCloseEndsTheSessionWithoutAFault(SerialUri());
}

TEST_GROUP(GadgetList){};

TEST(GadgetList, FindsTheGadgetByItsUsbIdAndProductStringOnEveryInterface) {
  bool hid = false, usb = false, serial = false;
  std::string all;
  for (const ph::FoundDevice& d : ph::ListDevices()) {
    all += d.uri + " '" + d.product + "' " + (d.palpa ? "palpa" : "-") + "\n";
    if (!d.palpa) continue;
    STRCMP_EQUAL("palpa actuator board", d.product.c_str());
    hid |= d.uri == "hid:1209:0001:0001";
    usb |= d.uri == "usb:1209:0001:0001";
    serial |= d.uri == SerialUri();
  }
  CHECK_TEXT(hid && usb && serial, all.c_str());
}
