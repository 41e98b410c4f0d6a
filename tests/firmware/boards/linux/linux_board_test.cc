// palpa-linux-board as a process, with the EK9000 emulator and a stand-in plant behind it: the
// link behaviour every board meets, safe outputs on SIGTERM, the module's watchdog after kill -9,
// a Modbus outage and a failed GPIO write (a fake libgpiod linked in) latched and reported over
// the link, refusals at start.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "board_behaviour.h"
#include "mini_client.h"
#include "palpa/host/device.h"
#include "palpa/host/fault_text.h"
#include "palpa/protocol/faults.h"
#include "sim_process.h"

// Last: both define CppUTest's allocation macros.
#include "CppUTest/TestHarness.h"
#include "ek9000_process.h"
#include "wait_until.h"

namespace pp = palpa::protocol;
namespace pt = palpa::testing;

namespace {

constexpr int kOutputs = 0x0800, kFallbacks = 0x1021;
// The module's settings a board writes when it opens it: watchdog time and type, fallback.
constexpr int kSettings[] = {0x1120, 0x1122, 0x1123};
// thesis-5finger's lines: a sensor reads 1 V at 0 Pa and 9 V at ±103.4 kPa; a regulator commands
// 0 to ±100 kPa with 0-10 V. Pressure lines 0-4 rise, vacuum lines 5-6 fall; channel 7 is spare.
constexpr const char* kVolts = "1,1,1,1,1,9,9,1";
const std::string kPlant =
    "plant=20:1/0.7736,1/0.7736,1/0.7736,1/0.7736,1/0.7736,9/-0.7736,9/-0.7736,1/0";

std::string Temp(const std::string& name) {
  return "/tmp/palpa-linux-board-" + std::to_string(getpid()) + "-" + name;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A board file for thesis-5finger on the emulator; `extra` adds top-level fields. The response
/// timeout is generous: the emulator is Python on a loaded machine, and only the outage the test
/// makes should latch a fault.
std::string WriteBoardFile(int module_port, const std::string& listen, const std::string& extra) {
  const std::string path = Temp("board.json");
  std::ofstream(path) << R"({"board": "thesis-5finger", "realtime": {"priority": 0},
    "link": {"listen": ")"
                      << listen << R"("}, "analog_module": {"port": )" << module_port
                      << R"(, "watchdog_ms": 500, "response_timeout_ms": 200,
    "outputs": {"count": 8}, "inputs": {"count": 8, "bits": 14}})"
                      << (extra.empty() ? "" : ", " + extra) << "}";
  return path;
}

/// A copy of board file FILE named NAME with the module's `host` set to HOST.
std::string WithModuleHost(const std::string& file, const std::string& host,
                           const std::string& name) {
  std::string text = ReadAll(file);
  const std::string section = "\"analog_module\": {";
  text.replace(text.find(section), section.size(), section + "\"host\": \"" + host + "\", ");
  std::ofstream(Temp(name)) << text;
  return Temp(name);
}

/// What a command printed on stdout.
std::string Run(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  char buffer[512];
  for (size_t n; p != nullptr && (n = fread(buffer, 1, sizeof(buffer), p)) > 0;)
    out.append(buffer, n);
  if (p != nullptr) pclose(p);
  return out;
}

/// palpa-linux-board linked against the fake libgpiod, its chip gpiochip0 declared, and the
/// environment variable `fault` (fake_gpiod_process.cc: which line fails, and how) naming `line`.
bool StartWithFakeGpio(pt::SimProcess& board, const std::string& file, const char* fault,
                       const char* line) {
  setenv("PALPA_FAKE_GPIOD_CHIPS", "gpiochip0", 1);
  setenv(fault, line, 1);
  const bool started = board.Start({file}, PALPA_LINUX_BOARD_FAKE_GPIO_PATH);
  unsetenv("PALPA_FAKE_GPIOD_CHIPS");
  unsetenv(fault);
  return started;
}

/// A host's configuration change is held to the module's fallback as the board file is: a safe
/// value 0 V does not command is refused whole, naming the line; one that keeps 0 V is taken.
void CheckSafeValueAwayFromZeroVoltsRefused(const std::string& address) {
  auto opened = palpa::host::Device::Open(address, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  palpa::host::Device& d = *opened.value;
  auto config = d.ReadConfig();
  CHECK_TEXT(config.ok(), config.message.c_str());
  palpa::host::BoardConfig changed = config.value;
  changed.lines[1].safe_pa = 20000;  // within line 1's limits: code 819, not 0 V
  // And a field the refusal must leave as it was.
  changed.board.telemetry_batch = config.value.board.telemetry_batch == 1 ? 2 : 1;
  const palpa::host::Outcome refused = d.ApplyConfig(changed);
  CHECK(refused.status == pp::Status::kBadValue);
  CHECK_TEXT(refused.message.find("(line ") != std::string::npos, refused.message.c_str());
  auto after = d.ReadConfig();
  CHECK_TEXT(after.ok(), after.message.c_str());
  LONGS_EQUAL(config.value.lines[1].safe_pa, after.value.lines[1].safe_pa);
  LONGS_EQUAL(config.value.board.telemetry_batch, after.value.board.telemetry_batch);
  changed.lines[1].safe_pa = config.value.lines[1].safe_pa;
  const palpa::host::Outcome kept = d.ApplyConfig(changed);
  CHECK_TEXT(kept.ok(), kept.message.c_str());
  CHECK(d.ApplyConfig(config.value).ok());
}

}  // namespace

TEST_GROUP(LinuxBoard){};

TEST(LinuxBoard, MeetsTheLinkBehaviourAndSigtermLeavesZeroVolts) {
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string watchdog = Temp("watchdog");
  std::ofstream(watchdog).close();  // a file stands in for /dev/watchdog: the kicks are its bytes
  const std::string file = WriteBoardFile(emulator.port(), "tcp:127.0.0.1:0",
                                          R"("watchdog": {"device": ")" + watchdog + R"("})");
  pt::SimProcess board;
  CHECK_TEXT(board.Start({file}, PALPA_LINUX_BOARD_PATH), board.output().c_str());
  CHECK(board.output().find("0 GPIO lines (none configured)") != std::string::npos);
  // Through the host library: Hello, a configuration change, line 0 at 40 kPa read back by its
  // sensor through the module (the closed loop), host silence making every line safe.
  pt::CheckBoardBehaviour(board.address(), pp::BoardKind::kLinux, /*plant_simulated=*/false);
  CheckSafeValueAwayFromZeroVoltsRefused(board.address());

  // The command line through a tcp: device URI.
  const std::string info =
      Run(std::string(PALPA_CLI_PATH) + " --device " + board.address() + " info");
  CHECK_TEXT(info.find("board         linux, id 1") != std::string::npos, info.c_str());
  CHECK_TEXT(info.find("configuration thesis-5finger") != std::string::npos, info.c_str());

  auto opened = palpa::host::Device::Open(board.address(), {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  CHECK(opened.value->ClearFault().ok());
  CHECK(opened.value->SetLines({{0, 60.0}}).ok());
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs) > 0x7FFF / 2; }, 3));
  kill(board.pid(), SIGTERM);  // with the session open and line 0 commanding 6 V
  LONGS_EQUAL(0, board.WaitExit(5000));
  opened.value.reset();
  for (int i = 0; i < 8; ++i) LONGS_EQUAL(0, emulator.Holding(kOutputs + i));
  LONGS_EQUAL(0, emulator.Holding(kFallbacks));  // written by the board, not by the module
  const std::string kicks = ReadAll(watchdog);
  CHECK(kicks.size() > 100 && kicks.find_first_not_of('k') == kicks.size() - 1);
  CHECK(kicks.back() == 'V');  // the magic close: a clean exit does not reset the machine
  unlink(watchdog.c_str());
  unlink(file.c_str());
}

TEST(LinuxBoard, AnOutageIsLatchedOverThePtyAndKillLeavesTheModuleToItsWatchdog) {
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string pty = Temp("pty");
  const std::string file = WriteBoardFile(emulator.port(), "pty:" + pty, "");
  pt::SimProcess board;
  CHECK_TEXT(board.Start({file}, PALPA_LINUX_BOARD_PATH), board.output().c_str());
  STRCMP_EQUAL(("serial:" + pty).c_str(), board.address().c_str());
  auto opened = palpa::host::Device::Open(board.address(), {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  palpa::host::Device& d = *opened.value;
  CHECK(d.info().board_kind == pp::BoardKind::kLinux);
  CHECK(d.SetLines({{1, 30.0}}).ok());
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs + 1) > 0; }, 3));

  emulator.Pause();  // the module falls silent: the tick's transfers time out
  const uint32_t output_write = pp::FaultBit(pp::Fault::kOutputWrite);
  uint32_t latched = 0;
  pt::WaitUntil(
      [&] {
        auto diag = d.Diagnostics();
        latched = diag.ok() ? diag.value.fault_bitmap : 0;
        return (latched & output_write) != 0;
      },
      5);
  emulator.Resume();
  CHECK_TEXT(latched & output_write, palpa::host::FaultNames(latched).c_str());
  // The module back (its backlog of stale requests answered first): the fault clears and the
  // board takes commands again.
  CHECK(pt::WaitUntil([&] { return d.ClearFault().ok(); }, 5));
  CHECK(d.SetLines({{1, 30.0}}).ok());
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs + 1) > 0; }, 3));
  const uint16_t fallbacks = emulator.Holding(kFallbacks);

  kill(board.pid(), SIGKILL);  // nothing writes the safe outputs now: the module's watchdog does
  LONGS_EQUAL(-1, board.WaitExit(5000));
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs + 1) == 0; }, 3));
  LONGS_EQUAL(fallbacks + 1, emulator.Holding(kFallbacks));
  unlink(file.c_str());
}

TEST(LinuxBoard, AGpioWriteThatFailsIsLatchedOverTheLinkAndTheBoardGoesSafe) {
  // The fake libgpiod in place of the real one: the supply enable's line refuses its values from
  // SIGUSR1 on, as a line whose chip went away does.
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string file = WriteBoardFile(emulator.port(), "tcp:127.0.0.1:0", R"("gpio": {
      "supply_enable": "gpiochip0:17", "dump_enable": "gpiochip0:18",
      "pump_enable": "gpiochip0:27", "valves": ["gpiochip0:5", "gpiochip0:6"]})");
  pt::SimProcess board;
  const bool started =
      StartWithFakeGpio(board, file, "PALPA_FAKE_GPIOD_FAIL_ON_SIGUSR1", "gpiochip0:17");
  CHECK_TEXT(started, board.output().c_str());
  CHECK_TEXT(board.output().find(", 5 GPIO lines") != std::string::npos, board.output().c_str());
  auto opened = palpa::host::Device::Open(board.address(), {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  palpa::host::Device& d = *opened.value;
  CHECK(d.SetLines({{1, 30.0}}).ok());
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs + 1) > 0; }, 3));
  auto before = d.Diagnostics();
  CHECK_TEXT(before.ok(), before.message.c_str());
  LONGS_EQUAL(0, before.value.fault_bitmap);

  kill(board.pid(), SIGUSR1);
  pp::Diagnostics diag{};
  pt::WaitUntil(
      [&] {
        auto read = d.Diagnostics();
        if (read.ok()) diag = read.value;
        return (diag.fault_bitmap & pp::FaultBit(pp::Fault::kOutputWrite)) != 0;
      },
      5);
  CHECK_TEXT(diag.fault_bitmap & pp::FaultBit(pp::Fault::kOutputWrite),
             palpa::host::FaultNames(diag.fault_bitmap).c_str());
  CHECK(diag.history_count >= 1);
  const pp::FaultRecord& record = diag.history[diag.history_count - 1];
  LONGS_EQUAL(static_cast<int>(pp::Fault::kOutputWrite), record.fault);
  LONGS_EQUAL(pp::OutputWriteDetail(pp::OutputKind::kSupplyEnable), record.detail);
  // Safe: line 1's regulator at 0 V; the host is refused new setpoints while the line fails.
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs + 1) == 0; }, 3));
  CHECK(d.SetLines({{1, 30.0}}).status == pp::Status::kFaulted);
  CHECK(d.ClearFault().status == pp::Status::kConditionPersists);

  // The exit's safe writes meet the same line: the module is at 0 V, the line is named.
  opened.value.reset();
  kill(board.pid(), SIGTERM);
  LONGS_EQUAL(1, board.WaitExit(5000));
  for (int i = 0; i < 8; ++i) LONGS_EQUAL(0, emulator.Holding(kOutputs + i));
  unlink(file.c_str());
}

TEST(LinuxBoard, AnUnreadableEStopLineIsLatchedAndItsReasonSaidOnce) {
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string file =
      WriteBoardFile(emulator.port(), "tcp:127.0.0.1:0", R"("gpio": {"estop": "gpiochip0:22"})");
  pt::SimProcess board;
  const bool started =
      StartWithFakeGpio(board, file, "PALPA_FAKE_GPIOD_UNREADABLE", "gpiochip0:22");
  CHECK_TEXT(started, board.output().c_str());
  // Said on stderr with the read's error, and only once: many ticks read the line after it.
  const std::string said =
      "palpa-linux-board: gpio.estop 'gpiochip0:22': reading the line's edges failed (Input/output "
      "error); the E-stop counts as pressed (estop_pin) from now on";
  CHECK(pt::WaitUntil(
      [&] { return (board.output() + board.later_output()).find(said) != std::string::npos; }, 3));
  auto opened = palpa::host::Device::Open(board.address(), {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  auto diag = opened.value->Diagnostics();
  CHECK_TEXT(diag.ok(), diag.message.c_str());
  CHECK(diag.value.fault_bitmap & pp::FaultBit(pp::Fault::kEStopPin));
  usleep(200000);
  const std::string all = board.output() + board.later_output();
  CHECK_TEXT(all.find(said) == all.rfind(said), all.c_str());
  opened.value.reset();
  LONGS_EQUAL(0, board.Stop());
  unlink(file.c_str());
}

TEST(LinuxBoard, ASecondBoardOnTheSameModuleIsRefusedBeforeItWritesToIt) {
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string file = WriteBoardFile(emulator.port(), "tcp:127.0.0.1:0", "");
  pt::SimProcess a;
  CHECK_TEXT(a.Start({file}, PALPA_LINUX_BOARD_PATH), a.output().c_str());
  auto opened = palpa::host::Device::Open(a.address(), {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  CHECK(opened.value->SetLines({{0, 60.0}}).ok());
  CHECK(pt::WaitUntil([&] { return emulator.Holding(kOutputs) > 0x7FFF / 2; }, 3));
  // A held still, so that whatever lands on the module now is B's: its watchdog off meanwhile,
  // and settings of values no board writes, which B's opening would overwrite.
  kill(a.pid(), SIGSTOP);
  usleep(50000);  // a transfer A had under way is answered
  uint16_t settings[3], marked[3] = {4321, 2, 1};
  for (int i = 0; i < 3; ++i) settings[i] = emulator.Holding(kSettings[i]);
  for (int i = 0; i < 3; ++i) emulator.SetHolding(kSettings[i], marked[i]);
  uint16_t outputs[8];
  for (int i = 0; i < 8; ++i) outputs[i] = emulator.Holding(kOutputs + i);

  // B: the same file, so the same module, no GPIO lines, and a TCP port of its own to bind.
  pt::SimProcess b;
  const bool b_started = b.Start({file}, PALPA_LINUX_BOARD_PATH);
  uint16_t settings_after[3], outputs_after[8];
  for (int i = 0; i < 3; ++i) settings_after[i] = emulator.Holding(kSettings[i]);
  for (int i = 0; i < 8; ++i) outputs_after[i] = emulator.Holding(kOutputs + i);
  const int b_exit = b.Stop();
  kill(a.pid(), SIGCONT);
  usleep(100000);  // A writes its outputs again before its module's watchdog is back on
  for (int i = 0; i < 3; ++i) emulator.SetHolding(kSettings[i], settings[i]);
  CHECK_TEXT(!b_started, b.output().c_str());
  LONGS_EQUAL(1, b_exit);
  const std::string refusal = "analog_module tcp:127.0.0.1:" + std::to_string(emulator.port()) +
                              " unit 1 is in use by process " + std::to_string(a.pid());
  CHECK_TEXT(b.output().find(refusal) != std::string::npos, b.output().c_str());
  for (int i = 0; i < 3; ++i) LONGS_EQUAL(marked[i], settings_after[i]);
  for (int i = 0; i < 8; ++i) LONGS_EQUAL(outputs[i], outputs_after[i]);

  // A serves its link and drives the module as before.
  auto config = opened.value->ReadConfig();
  CHECK_TEXT(config.ok(), config.message.c_str());
  CHECK(opened.value->SetLines({{0, 30.0}}).ok());
  CHECK(pt::WaitUntil(
      [&] { return emulator.Holding(kOutputs) < outputs[0] && emulator.Holding(kOutputs) > 0; },
      3));
  opened.value.reset();
  LONGS_EQUAL(0, a.Stop());
  unlink(file.c_str());
}

TEST(LinuxBoard, TwoNamesOfOneModuleAreOneClaim) {
  // A configured with a name of the module (which it connects to), B with its address: B is
  // refused as a board with the same file is, naming A.
  pt::Ek9000Emulator emulator(kVolts, kPlant);
  CHECK(emulator.up());
  const std::string file = WriteBoardFile(emulator.port(), "tcp:127.0.0.1:0", "");
  const std::string named = WithModuleHost(file, "localhost", "named.json");
  pt::SimProcess a;
  const bool a_started = a.Start({named}, PALPA_LINUX_BOARD_PATH);
  CHECK_TEXT(a_started, a.output().c_str());
  pt::SimProcess b;
  const bool b_started = b.Start({file}, PALPA_LINUX_BOARD_PATH);
  CHECK_TEXT(!b_started, b.output().c_str());
  LONGS_EQUAL(1, b.WaitExit(5000));
  const std::string refusal = "analog_module tcp:127.0.0.1:" + std::to_string(emulator.port()) +
                              " unit 1 is in use by process " + std::to_string(a.pid());
  CHECK_TEXT(b.output().find(refusal) != std::string::npos, b.output().c_str());
  LONGS_EQUAL(0, a.Stop());
  unlink(named.c_str());
  unlink(file.c_str());
}

TEST(LinuxBoard, RefusesABadFileOrAMissingModuleAndSaysWhy) {
  pt::SimProcess board;
  const std::string file = WriteBoardFile(1, "tcp:127.0.0.1:0", R"("gpio": {"valves": [3]})");
  CHECK(!board.Start({file}, PALPA_LINUX_BOARD_PATH));
  CHECK_TEXT(board.output().find("gpio.valves[0]: expected CHIP:LINE") != std::string::npos,
             board.output().c_str());
  LONGS_EQUAL(2, board.WaitExit(5000));
  // Nothing answers Modbus at the port: refused at start, naming the module.
  const std::string nothing = WriteBoardFile(pt::FreeTcpPort(), "tcp:127.0.0.1:0", "");
  pt::SimProcess none;
  CHECK(!none.Start({nothing}, PALPA_LINUX_BOARD_PATH));
  CHECK_TEXT(none.output().find("analog_module: tcp:127.0.0.1:") != std::string::npos,
             none.output().c_str());
  LONGS_EQUAL(1, none.WaitExit(5000));
  // A host name that does not resolve: refused before anything is claimed, naming it and its key.
  const std::string unknown = WithModuleHost(nothing, "no-such-module.invalid", "unknown.json");
  pt::SimProcess unnamed;
  CHECK(!unnamed.Start({unknown}, PALPA_LINUX_BOARD_PATH));
  CHECK_TEXT(unnamed.output().find(unknown + ": analog_module.host: 'no-such-module.invalid' does "
                                             "not resolve") != std::string::npos,
             unnamed.output().c_str());
  LONGS_EQUAL(1, unnamed.WaitExit(5000));
  unlink(unknown.c_str());
  unlink(file.c_str());
}
