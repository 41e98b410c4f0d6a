// Runs inside the real-kernel guest (tests/kernel/linux_board): palpa-linux-board as the USB gadget
// on dummy_hcd, its valves and E-stop on gpio-mockup lines, its watchdog on the i6300esb, its
// analogue I/O module the EK9000 emulator with a stand-in plant on the machine running QEMU; the
// host library on dummy_hcd's host side. The watchdog resets the machine (ending the scenario in a
// failure) if the board does not kick it.
//   PALPA_GPIO_CHIP  the gpio-mockup chip (8 lines: the valves on 0-6, the E-stop on 7)
//   PALPA_MODULE     the emulator's HOST:PORT (10.0.2.2:PORT over QEMU's user network)
#include <fcntl.h>
#include <modbus.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "board_behaviour.h"
#include "gadget_link.h"
#include "mini_client.h"
#include "palpa/hal/linux/watchdog_device.h"
#include "palpa/host/device.h"
#include "palpa/host/fault_text.h"
#include "palpa/protocol/faults.h"
#include "sim_process.h"
#include "wait_until.h"

#include "CppUTest/CommandLineTestRunner.h"
#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;
namespace pt = palpa::testing;

namespace {

constexpr int kOutputs = 0x0800, kFallbacks = 0x1021;
constexpr int kValves = 7, kEstopLine = 7;
constexpr const char* kUsb = "usb:1209:0001";

std::string Env(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr ? value : "";
}

std::string LinePath(int line) {
  return "/sys/kernel/debug/gpio-mockup/" + Env("PALPA_GPIO_CHIP") + "/" + std::to_string(line);
}
int Level(int line) {
  std::ifstream in(LinePath(line));
  int level = -1;
  in >> level;
  return level;
}
void Pull(int line, int level) { std::ofstream(LinePath(line)) << level; }

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A second Modbus client on the emulator: what the module's registers hold.
class ModuleProbe {
 public:
  ModuleProbe() {
    const std::string at = Env("PALPA_MODULE");
    host_ = at.substr(0, at.find(':'));
    ctx_ = modbus_new_tcp(host_.c_str(), std::atoi(at.c_str() + at.find(':') + 1));
    modbus_set_response_timeout(ctx_, 2, 0);
  }
  ~ModuleProbe() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  int Holding(int address) {
    uint16_t v = 0;
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (modbus_read_registers(ctx_, address, 1, &v) == 1) return v;
      modbus_close(ctx_);
      modbus_connect(ctx_);
    }
    return -1;
  }

 private:
  std::string host_;
  modbus_t* ctx_;
};

/// thesis-5finger on the emulator, the valves and the E-stop on the mockup chip, the watchdog,
/// the link on the gadget. The response timeout is generous: the module is across QEMU's user
/// network on a loaded machine, and only the outage the test makes should latch a fault.
std::string BoardFile() {
  const std::string at = Env("PALPA_MODULE"), chip = Env("PALPA_GPIO_CHIP");
  std::string valves;
  for (int i = 0; i < kValves; ++i)
    valves += (i ? ", \"" : "\"") + chip + ":" + std::to_string(i) + "\"";
  const std::string path = "/tmp/board.json";
  std::ofstream(path) << R"({"board": "thesis-5finger", "realtime": {"priority": 0},
    "link": {"listen": "usb"}, "watchdog": {"device": "/dev/watchdog", "timeout_s": 2},
    "analog_module": {"host": ")"
                      << at.substr(0, at.find(':')) << R"(", "port": )"
                      << at.substr(at.find(':') + 1)
                      << R"(, "watchdog_ms": 2000, "response_timeout_ms": 1000,
      "outputs": {"count": 8}, "inputs": {"count": 8, "bits": 14}},
    "gpio": {"valves": [)"
                      << valves << "], \"estop\": \"" << chip << ":" << kEstopLine << "\"}}";
  return path;
}

/// Starts the board and waits until the host side has enumerated its three interfaces.
void StartBoard(pt::SimProcess& board) {
  CHECK_TEXT(board.Start({BoardFile()}, "/bin/palpa-linux-board"), board.output().c_str());
  STRCMP_EQUAL(kUsb, board.address().c_str());
  CHECK_TEXT(
      pt::WaitUntil(
          [] { return access("/dev/hidraw0", F_OK) == 0 && access("/dev/ttyACM0", F_OK) == 0; },
          15),
      "the board's gadget did not enumerate");
}

/// A second claim on the board's gadget, as a second board or palpa-gadget would make: refused
/// while its owner runs, naming it; *error says why.
bool SecondGadgetOpens(std::string* error) {
  palpa::gadget::GadgetLink second;
  return second.Open({}, error);
}

/// The board answers on `address` (Hello and its diagnostics, what palpa info asks); returns the
/// boot it reports.
uint32_t CheckAnswers(const std::string& address) {
  auto opened = palpa::host::Device::Open(address, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());  // the message names the address
  CHECK(opened.value->info().board_kind == pp::BoardKind::kLinux);
  auto diag = opened.value->Diagnostics();
  CHECK_TEXT(diag.ok(), (address + ": " + diag.message).c_str());
  return opened.value->info().boot_nonce;
}

uint32_t Latched(palpa::host::Device& d) {
  auto diag = d.Diagnostics();
  return diag.ok() ? diag.value.fault_bitmap : 0;
}

}  // namespace

TEST_GROUP(LinuxBoardGuest){};

TEST(LinuxBoardGuest, MeetsTheLinkBehaviourThroughUsbKillLeavesEverythingSafeAndARestartServes) {
  Pull(kEstopLine, 0);
  pt::SimProcess board;
  StartBoard(board);
  // Host silence at 1 s: the board's ticks run late here (each waits on the module across QEMU's
  // user network: tens of ms), and 150 ms would cut the session short.
  pt::CheckBoardBehaviour(kUsb, pp::BoardKind::kLinux, /*plant_simulated=*/false, 1000000);
  std::string refused;
  CHECK_FALSE(SecondGadgetOpens(&refused));  // the running board's gadget is not taken from it
  CHECK_TEXT(refused.find("gadget palpa is in use by process " + std::to_string(board.pid())) !=
                 std::string::npos,
             refused.c_str());

  ModuleProbe module;
  auto opened = palpa::host::Device::Open(kUsb, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  const uint32_t board_boot = opened.value->info().boot_nonce;
  if (auto loop = opened.value->LoopStats(); loop.ok()) {  // figures for docs/kernel_tests.md
    std::printf("\nlinux board: %llu ticks, %u overruns, jitter max %u us, worst tick %u us\n",
                static_cast<unsigned long long>(loop.value.ticks), loop.value.overruns,
                loop.value.jitter_max_us, loop.value.worst_tick_us);
  }
  CHECK(opened.value->ClearFault().ok());
  CHECK(opened.value->SetLines({{0, 60.0}, {1, 30.0}}).ok());
  CHECK_TEXT(pt::WaitUntil([&] { return module.Holding(kOutputs) > 0x7FFF / 2; }, 5),
             "line 0's 6 V did not reach the module");
  CHECK_TEXT(pt::WaitUntil([] { return Level(0) == 1 && Level(1) == 1; }, 2),
             "lines 0 and 1's valve drivers are not powered while they are commanded");
  const int fallbacks = module.Holding(kFallbacks);
  STRCMP_EQUAL("active\n", ReadAll("/sys/class/watchdog/watchdog0/state").c_str());

  kill(board.pid(), SIGKILL);  // nothing writes the safe outputs: the module's watchdog does
  LONGS_EQUAL(-1, board.WaitExit(5000));
  opened.value.reset();
  // Closed without the magic character, the watchdog stays armed and would reset the machine in
  // 2 s (which ends the scenario): a controller taking over now stops it.
  STRCMP_EQUAL("active\n", ReadAll("/sys/class/watchdog/watchdog0/state").c_str());
  auto takeover_opened = palpa::hal::linux_wdt::WatchdogDevice::Open("/dev/watchdog", 0);
  CHECK_TEXT(takeover_opened.ok(), takeover_opened.message.c_str());
  auto takeover = std::move(takeover_opened.value);
  CHECK_TEXT(takeover->Close(), takeover->error().c_str());
  CHECK_TEXT(pt::WaitUntil([&] { return module.Holding(kOutputs) == 0; }, 8),
             "the module's output 0 did not fall to 0 V after the controller died");
  for (int i = 0; i < 8; ++i) LONGS_EQUAL(0, module.Holding(kOutputs + i));
  LONGS_EQUAL(fallbacks + 1, module.Holding(kFallbacks));      // the module's watchdog, once
  for (int i = 0; i < kValves; ++i) LONGS_EQUAL(0, Level(i));  // released: the pull-down

  // The killed board's gadget stays in configfs with its FunctionFS instances mounted. While a
  // program holds one of them open (one that does not claim the name) it is not taken down...
  const int ep0 = open("/run/palpa-gadget/palpa_bulk/ep0", O_RDWR);
  CHECK(ep0 >= 0);
  CHECK_FALSE(SecondGadgetOpens(&refused));
  close(ep0);
  CHECK_TEXT(refused.find("palpa_bulk (/run/palpa-gadget/palpa_bulk) is open in a running") !=
                 std::string::npos,
             refused.c_str());
  // ...and without one, a board started again removes it, makes its own and serves the host on
  // each of its interfaces: vendor bulk, HID, the ACM port.
  pt::SimProcess again;
  StartBoard(again);
  CHECK_TEXT(again.output().find("removed the USB gadget a program that died left behind") !=
                 std::string::npos,
             again.output().c_str());
  const uint32_t boot = CheckAnswers(kUsb);
  CHECK(boot != board_boot);  // a new boot to the host
  LONGS_EQUAL(boot, CheckAnswers("hid:1209:0001"));
  LONGS_EQUAL(boot, CheckAnswers("serial:/dev/ttyACM0"));
  LONGS_EQUAL(0, again.Stop());
  STRCMP_EQUAL("inactive\n", ReadAll("/sys/class/watchdog/watchdog0/state").c_str());
}

TEST(LinuxBoardGuest, TheEstopLineAndAModbusOutageLatchFaultsReadOverUsb) {
  Pull(kEstopLine, 0);
  pt::SimProcess board;
  StartBoard(board);
  auto opened = palpa::host::Device::Open(kUsb, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  palpa::host::Device& d = *opened.value;
  CHECK(d.ClearFault().ok());
  CHECK(d.SetLines({{0, 20.0}}).ok());

  const uint32_t estop = pp::FaultBit(pp::Fault::kEStopPin);
  Pull(kEstopLine, 1);  // pressed
  CHECK_TEXT(pt::WaitUntil([&] { return (Latched(d) & estop) != 0; }, 3),
             "the E-stop line's press was not latched");
  CHECK_TEXT(pt::WaitUntil([] { return Level(0) == 0; }, 2), "line 0's valve stayed powered");
  Pull(kEstopLine, 0);
  CHECK(pt::WaitUntil([&] { return d.ClearFault().ok(); }, 3));

  // The module unreachable (its network gone): the tick's transfers time out.
  const uint32_t output_write = pp::FaultBit(pp::Fault::kOutputWrite);
  CHECK(std::system("ip link set eth0 down") == 0);
  uint32_t latched = 0;
  pt::WaitUntil([&] { return ((latched = Latched(d)) & output_write) != 0; }, 8);
  CHECK(std::system("ip link set eth0 up") == 0);
  CHECK_TEXT(latched & output_write, palpa::host::FaultNames(latched).c_str());
  opened.value.reset();
  LONGS_EQUAL(0, board.Stop());
  STRCMP_EQUAL("inactive\n", ReadAll("/sys/class/watchdog/watchdog0/state").c_str());
}

int main(int argc, char** argv) { return CommandLineTestRunner::RunAllTests(argc, argv); }
