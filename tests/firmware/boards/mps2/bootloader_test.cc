// The bootloader on the Cortex-M4F under QEMU: an application image (made by the build step,
// make_image.py) boots through it — checked and jumped to — and answers Hello, and after a reboot
// it asked for says why it started; a corrupted one leaves the board in recovery mode; and from
// recovery `palpa flash` writes a release, the board boots it in trial (reporting the update as
// its reset cause), and the host confirms it; an update its host abandoned holds the board only
// until the next session.
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/flasher.h"
#include "palpa/host/link.h"
#include "qemu_process.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::testing::QemuProcess;

namespace {

const std::string kBoot = std::string(PALPA_BOOT_DIR) + "/palpa-mps2-boot.elf";
std::string SlotImage(int slot) {
  return std::string(PALPA_BOOT_DIR) + "/palpa-mps2-slot" + std::to_string(slot) + ".img";
}

std::vector<uint8_t> Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::unique_ptr<ph::Link> Connect(const QemuProcess& qemu) {
  auto t = ph::OpenTransport(qemu.address());
  CHECK_TEXT(t.ok(), t.message.c_str());
  auto link = ph::Link::Open(std::move(t.value), ph::LinkOptions{});
  CHECK_TEXT(link.ok(), link.message.c_str());
  return std::move(link.value);
}

/// The release as the build step made it (Python); the host's parser must accept it.
ph::UpdatePackage BuildStepRelease() {
  auto package = ph::ReadPackage(Read(std::string(PALPA_BOOT_DIR) + "/palpa-mps2.palpa"));
  CHECK_TEXT(package.ok(), package.message.c_str());
  return std::move(package.value);
}

bool ImagesBuilt() {
  return access(kBoot.c_str(), R_OK) == 0 && access(SlotImage(1).c_str(), R_OK) == 0;
}

/// The bootloader and slot 0's application on QEMU's instruction clock (-icount): the watchdog
/// then measures the firmware's own work, not how the host schedules QEMU.
void StartOnInstructionClock(QemuProcess& qemu) {
  CHECK(qemu.Start(PALPA_QEMU, {"-icount", "shift=5,align=on", "-kernel", kBoot, "-device",
                                "loader,file=" + SlotImage(0) + ",addr=0x8000,force-raw=on"}));
}

/// A device on that board whose session allows 10 s of host silence: the host's heartbeats are
/// paced in real time, which the instruction clock is not.
std::unique_ptr<ph::Device> OpenPatientDevice(const QemuProcess& qemu) {
  auto device = ph::Device::Open(qemu.address(), {});
  CHECK_TEXT(device.ok(), device.message.c_str());
  auto board = device.value->ReadBoard();
  CHECK_TEXT(board.ok(), board.message.c_str());
  board.value.host_timeout_us = 10000000;
  CHECK(device.value->ConfigureBoard(board.value).ok());
  return std::move(device.value);
}

}  // namespace

TEST_GROUP(QemuBootloader){};

TEST(QemuBootloader, AnImageInEitherSlotBootsThroughTheBootloaderAndAnswers) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  for (int slot : {0, 1}) {
    const std::string addr = slot == 0 ? "0x8000" : "0x38000";
    QemuProcess qemu;
    CHECK(qemu.Start(PALPA_QEMU,
                     {"-kernel", kBoot, "-device",
                      "loader,file=" + SlotImage(slot) + ",addr=" + addr + ",force-raw=on"}));
    auto link = Connect(qemu);
    const pp::HelloReply hello = link->board();
    STRCMP_EQUAL("thesis-5finger", hello.config_name.data());
    LONGS_EQUAL(1, hello.firmware_minor);
    LONGS_EQUAL(slot, hello.active_slot);  // the application runs where the bootloader put it
    CHECK(link->catalog_matches());
  }
}

TEST(QemuBootloader, ARebootAskedOfTheApplicationComesBackSayingWhy) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  QemuProcess qemu;
  CHECK(qemu.Start(PALPA_QEMU, {"-kernel", kBoot, "-device",
                                "loader,file=" + SlotImage(0) + ",addr=0x8000,force-raw=on"}));
  auto link = Connect(qemu);
  CHECK(link->board().reset_cause == pp::ResetCause::kPowerOn);
  const uint32_t nonce = link->board().boot_nonce;
  LONGS_EQUAL((int)pp::Status::kOk, (int)link->Command(pp::UpdateReboot{}).status);
  // The application records the cause, resets into the bootloader, which boots it again.
  for (int i = 0; i < 500 && !(link->session_open() && link->board().boot_nonce != nonce); ++i) {
    usleep(10000);
  }
  CHECK_TEXT(link->board().boot_nonce != nonce, "no new session after the reboot");
  LONGS_EQUAL((int)pp::ResetCause::kUpdate, (int)link->board().reset_cause);
  pp::Diagnostics diagnostics{};
  CHECK(link->Command(pp::GetDiagnostics{}).Reply(diagnostics));
  LONGS_EQUAL(2, diagnostics.boot_count);  // counted across the reset, not started again
}

TEST(QemuBootloader, ACorruptedImageLeavesTheBoardInRecoveryMode) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  std::vector<uint8_t> image = Read(SlotImage(0));
  image[image.size() / 2] ^= 0x20;  // one bit of the body
  const std::string bad = "/tmp/palpa-bad-slot0-" + std::to_string(getpid()) + ".img";
  std::ofstream(bad, std::ios::binary)
      .write(reinterpret_cast<const char*>(image.data()),
             static_cast<std::streamsize>(image.size()));
  QemuProcess qemu;
  CHECK(qemu.Start(PALPA_QEMU, {"-kernel", kBoot, "-device",
                                "loader,file=" + bad + ",addr=0x8000,force-raw=on"}));
  auto link = Connect(qemu);
  const pp::HelloReply hello = link->board();
  STRCMP_EQUAL("recovery", hello.config_name.data());
  LONGS_EQUAL(0, hello.firmware_major + hello.firmware_minor + hello.firmware_patch);
  // Recovery speaks the bootstrap set and nothing else.
  const ph::CommandResult r = link->Command(pp::GetDiagnostics{});
  LONGS_EQUAL((int)pp::Status::kUnsupported, (int)r.status);
  pp::SlotsReport slots{};
  CHECK(link->Command(pp::SlotsQuery{}).Reply(slots));
  CHECK(slots.slots[0].state == pp::SlotState::kInvalid);
  CHECK(slots.slots[1].state == pp::SlotState::kEmpty);
  unlink(bad.c_str());
}

TEST(QemuBootloader, FromRecoveryAFlashedReleaseBootsInTrialAndIsConfirmed) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  const ph::UpdatePackage package = BuildStepRelease();
  QemuProcess qemu;  // the bootloader alone: both slots empty
  CHECK(qemu.Start(PALPA_QEMU, {"-kernel", kBoot}));
  auto link = Connect(qemu);
  STRCMP_EQUAL("recovery", link->board().config_name.data());
  CHECK(link->board().reset_cause == pp::ResetCause::kPowerOn);  // nothing recorded before
  const ph::FlashReport r = ph::FlashPackage(*link, package, {});
  CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
  const pp::HelloReply after = link->board();
  STRCMP_EQUAL("thesis-5finger", after.config_name.data());
  LONGS_EQUAL(r.slot, after.active_slot);
  LONGS_EQUAL(1, after.firmware_minor);
  // The bootloader left the application's reset record before its reboot: the release says why
  // it started, as after an update through the application.
  LONGS_EQUAL((int)pp::ResetCause::kUpdate, (int)after.reset_cause);
  pp::SlotsReport slots{};
  CHECK(link->Command(pp::SlotsQuery{}).Reply(slots));
  CHECK(slots.slots[r.slot].state == pp::SlotState::kConfirmed);
}

TEST(QemuBootloader, ThroughTheApplicationAReleaseIsFlashedBootedAndConfirmed) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  const ph::UpdatePackage package = BuildStepRelease();
  // Time paced by instructions (32 ns each, about the MPS2's 25 MHz): the application's 30 ms
  // watchdog measures the firmware's own work, as on the board, not how the host schedules QEMU.
  // That time is not real time: a free core runs the image faster than 25 MHz (align=on holds
  // it back, but it catches up after a late spell at full speed), and the host's heartbeats,
  // paced in real time, would miss a 100 ms host-silence timeout now and then. The session gets
  // 10 s, as a host on such a clock would give it.
  QemuProcess qemu;
  StartOnInstructionClock(qemu);
  const auto device = OpenPatientDevice(qemu);
  ph::Link* link = &device->link();
  STRCMP_EQUAL("thesis-5finger", link->board().config_name.data());
  const ph::FlashReport r = ph::FlashPackage(*link, package, {});
  CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
  LONGS_EQUAL(1, r.slot);  // the slot the application was not running from
  const pp::HelloReply after = link->board();
  LONGS_EQUAL(1, after.active_slot);
  LONGS_EQUAL((int)pp::ResetCause::kUpdate, (int)after.reset_cause);
  pp::SlotsReport slots{};
  CHECK(link->Command(pp::SlotsQuery{}).Reply(slots));
  CHECK(slots.slots[1].state == pp::SlotState::kConfirmed);
  CHECK(slots.slots[0].state == pp::SlotState::kValid);
}

TEST(QemuBootloader, ACommandLongerThanTheWatchdogPeriodLeavesAnActuatingApplicationRunning) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  // A slots query hashes both images: about 300 ms of this core, the watchdog kicked through it.
  // The simulated plant then catches up with those 300 ms before the next tick, and that must
  // not count as the firmware's work (it once took 50 ms and the watchdog reset the board).
  QemuProcess qemu;
  StartOnInstructionClock(qemu);
  const auto device = OpenPatientDevice(qemu);
  ph::Link& link = device->link();
  const uint32_t boot = link.board().boot_nonce;
  const ph::Outcome set = device->SetLines({{0, 60.0}});  // a plant at work
  CHECK_TEXT(set.ok(), set.message.c_str());
  for (int i = 0; i < 3; ++i) {
    pp::SlotsReport slots{};
    const ph::CommandResult r = link.Command(pp::SlotsQuery{});
    LONGS_EQUAL((int)pp::Status::kOk, (int)r.status);
    CHECK(r.Reply(slots));
  }
  LONGS_EQUAL(boot, link.board().boot_nonce);  // never reset
  LONGS_EQUAL(0, device->info().fault_bitmap);
}

TEST(QemuBootloader, AnUpdateItsHostClosesMidwayLeavesNoFaultAndCanResume) {
  CHECK_TEXT(ImagesBuilt(), "the mps2 preset's images are missing");
  const ph::UpdatePackage package = BuildStepRelease();
  const std::vector<uint8_t>& image = package.slot_image[1];
  const auto size = static_cast<uint32_t>(image.size());
  QemuProcess qemu;
  StartOnInstructionClock(qemu);
  {  // A host starts an update, writes its first chunk and closes its session.
    auto device = ph::Device::Open(qemu.address(), {});
    CHECK_TEXT(device.ok(), device.message.c_str());
    ph::Link& link = device.value->link();
    LONGS_EQUAL((int)pp::Status::kOk, (int)link.Command(pp::UpdateEnter{1, size}).status);
    LONGS_EQUAL((int)pp::Status::kOk, (int)link.Command(pp::UpdateErase{1, 0, size}, 60000).status);
    pp::UpdateWrite first;
    first.slot = 1;
    first.data_size = 200;
    std::copy(image.begin(), image.begin() + 200, first.data.begin());
    LONGS_EQUAL((int)pp::Status::kOk, (int)link.Command(first).status);
    LONGS_EQUAL((int)pp::Status::kBusy, (int)device.value->SetLines({{0, 20.0}}).status);
  }
  // The next host's session is not held by it, and no fault was left: its setpoints are taken.
  auto device = ph::Device::Open(qemu.address(), {});
  CHECK_TEXT(device.ok(), device.message.c_str());
  ph::Link& link = device.value->link();
  LONGS_EQUAL(0, device.value->info().fault_bitmap);
  pp::UpdateStatus status{};
  CHECK(link.Command(pp::UpdateQuery{1}).Reply(status));
  CHECK_FALSE(status.in_update_mode);
  LONGS_EQUAL(200, status.written_bytes);
  const ph::Outcome set = device.value->SetLines({{0, 20.0}});
  CHECK_TEXT(set.ok(), set.message.c_str());
  // And an update of the same image goes on from what was written.
  LONGS_EQUAL((int)pp::Status::kOk, (int)link.Command(pp::UpdateEnter{1, size}).status);
  CHECK(link.Command(pp::UpdateQuery{1}).Reply(status));
  CHECK(status.in_update_mode);
  LONGS_EQUAL(200, status.written_bytes);
  CHECK(status.written_sha256 == pp::Sha256Of(image.data(), 200));
}
