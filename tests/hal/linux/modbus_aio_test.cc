// The Modbus analogue I/O module against an emulated EK9000 coupler (pymodbus, its watchdog too).
#include <modbus.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>

#include "child_process.h"
#include "ek9000_process.h"
#include "palpa/hal/linux/modbus_aio.h"
#include "sim_process.h"
#include "wait_until.h"

#include "CppUTest/TestHarness.h"

namespace aio = palpa::hal::linux_aio;
using palpa::protocol::Status;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kWatchdogMs = 300;

using palpa::testing::Ek9000Emulator;
using palpa::testing::WaitUntil;

// The emulator with this file's watchdog time and response timeout.
class Emulator : public Ek9000Emulator {
 public:
  explicit Emulator(const char* input_volts) : Ek9000Emulator(input_volts) {}
  aio::ModbusAioConfig Config() const {
    aio::ModbusAioConfig c;
    c.port = port();
    c.watchdog_ms = kWatchdogMs;
    c.response_timeout_ms = 100;
    return c;
  }
};

// What the coupler's EL4004 holds for counts of a 12-bit output: 0x7FFF is 10 V.
uint16_t ExpectedCode(uint32_t counts) {
  return static_cast<uint16_t>(std::lround(counts / 4095.0 * 0x7FFF));
}

std::unique_ptr<aio::ModbusAioModule> OpenOrFail(const aio::ModbusAioConfig& config) {
  auto opened = aio::ModbusAioModule::Open(config);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  return std::move(opened.value);
}

}  // namespace

TEST_GROUP(ModbusAio){};

TEST(ModbusAio, StartArmsTheWatchdogAndWritesTheSafeValues) {
  Emulator emulator("0,0,0,0");
  CHECK(emulator.up());
  for (int i = 0; i < 4; ++i) emulator.SetHolding(0x0800 + i, 12345);  // left by an earlier run
  emulator.SetHolding(0x1123, 1);                                      // freeze: not safe
  auto module = OpenOrFail(emulator.Config());
  LONGS_EQUAL(kWatchdogMs, emulator.Holding(0x1120));
  LONGS_EQUAL(0, emulator.Holding(0x1122));  // retriggered by writes only
  LONGS_EQUAL(0, emulator.Holding(0x1123));  // outputs to zero on a timeout
  for (int i = 0; i < 4; ++i) LONGS_EQUAL(0, emulator.Holding(0x0800 + i));
}

// libmodbus connects to an IPv4 literal only: a host name is resolved first, and one that does
// not resolve is refused naming it.
TEST(ModbusAio, AModuleNamedByItsHostIsReachedAndAnUnknownNameRefused) {
  Emulator emulator("0,0,0,0");
  CHECK(emulator.up());
  aio::ModbusAioConfig config = emulator.Config();
  config.host = "localhost";
  auto module = OpenOrFail(config);
  const uint32_t counts[4] = {4095, 0, 0, 0};
  LONGS_EQUAL(palpa::hal::AnalogOutput::kAllWritten, module->outputs().WriteAll(counts, 4));
  LONGS_EQUAL(0x7FFF, emulator.Holding(0x0800));
  config.host = "no-such-module.invalid";  // RFC 6761: never resolves
  const auto refused = aio::ModbusAioModule::Open(config);
  CHECK(refused.value == nullptr && refused.status == Status::kNotFound);
  const std::string where = "tcp:no-such-module.invalid:" + std::to_string(config.port) +
                            " unit 1: 'no-such-module.invalid' does not resolve to an IPv4 address";
  CHECK_TEXT(refused.message.rfind(where, 0) == 0, refused.message.c_str());
}

TEST(ModbusAio, OutputsReachTheRegistersScaledAndInputsReadBackScaled) {
  Emulator emulator("1,2.5,5,10");
  CHECK(emulator.up());
  auto module = OpenOrFail(emulator.Config());
  aio::ModbusAioModule& m = *module;
  LONGS_EQUAL(12, m.outputs().spec(0).bits);
  const uint32_t counts[4] = {0, 1, 2048, 4095};
  LONGS_EQUAL(palpa::hal::AnalogOutput::kAllWritten, m.outputs().WriteAll(counts, 4));
  for (int i = 0; i < 4; ++i) LONGS_EQUAL(ExpectedCode(counts[i]), emulator.Holding(0x0800 + i));
  CHECK(m.outputs().Write(2, 1000) == Status::kOk);
  LONGS_EQUAL(ExpectedCode(1000), emulator.Holding(0x0802));
  // Beyond the line's range nothing is written, in one channel or in a scan.
  CHECK(m.outputs().Write(2, 4096) == Status::kOutOfRange);
  const uint32_t too_high[4] = {5, 5, 4096, 5};
  LONGS_EQUAL(2, m.outputs().WriteAll(too_high, 4));
  LONGS_EQUAL(ExpectedCode(1000), emulator.Holding(0x0802));
  LONGS_EQUAL(ExpectedCode(1), emulator.Holding(0x0801));
  CHECK(m.outputs().Write(4, 0) == Status::kNotFound);

  LONGS_EQUAL(12, m.inputs().bits());
  uint32_t read[5];
  m.inputs().ReadAll(read, 5);
  const double volts[4] = {1, 2.5, 5, 10};
  for (int i = 0; i < 4; ++i) DOUBLES_EQUAL(volts[i] / 10 * 4095, read[i], 1.0);
  LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, read[4]);  // no fifth channel
  const auto one = m.inputs().Read(3);
  CHECK(one.ok());
  LONGS_EQUAL(4095, one.value);
  // A code no 0-10 V terminal gives (negative, over range) is no reading.
  LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, m.InputCounts(0x8000));
}

TEST(ModbusAio, AnInputTheTerminalMarksInvalidIsNoReading) {
  Emulator emulator("1,nan,5,10");  // channel 1's wire broken: full scale, with the error bit
  CHECK(emulator.up());
  auto module = OpenOrFail(emulator.Config());
  uint32_t read[4];
  module->inputs().ReadAll(read, 4);
  LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, read[1]);
  DOUBLES_EQUAL(409.5, read[0], 1.0);
  LONGS_EQUAL(4095, read[3]);
}

TEST(ModbusAio, KillingTheControllerLeavesTheOutputsAtTheirSafeValues) {
  Emulator emulator("0,0,0,0");
  CHECK(emulator.up());
  const aio::ModbusAioConfig config = emulator.Config();
  const uint32_t counts[4] = {1000, 2000, 3000, 4000};
  const pid_t controller = fork();
  if (controller == 0) {  // a controller ticking its outputs every 10 ms until it is killed
    auto m = aio::ModbusAioModule::Open(config).value;
    while (m != nullptr) {
      m->outputs().WriteAll(counts, 4);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    _exit(1);
  }
  palpa::testing::ChildProcess controller_process(controller, SIGKILL);
  auto driven = [&] {
    for (int i = 0; i < 4; ++i) {
      if (emulator.Holding(0x0800 + i) != ExpectedCode(counts[i])) return false;
    }
    return true;
  };
  CHECK(WaitUntil(driven, 10));
  // Alive, it keeps the module's watchdog from firing for several watchdog times.
  std::this_thread::sleep_for(std::chrono::milliseconds(3 * kWatchdogMs));
  CHECK(driven());
  LONGS_EQUAL(0, emulator.Holding(0x1021));
  const auto killed = Clock::now();
  controller_process.Stop();
  auto safe = [&] {
    for (int i = 0; i < 4; ++i) {
      if (emulator.Holding(0x0800 + i) != 0) return false;
    }
    return true;
  };
  CHECK(WaitUntil(safe, 10));
  LONGS_EQUAL(1, emulator.Holding(0x1021));  // one fallback: the watchdog's, not a write of zeros
  std::printf(
      "\n  outputs at zero %lld ms after kill -9 (watchdog %d ms)\n",
      static_cast<long long>(
          std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - killed).count()),
      kWatchdogMs);
}

TEST(ModbusAio, AnOutageIsAnErrorNeverAStaleValue) {
  Emulator emulator("5,5,5,5");
  CHECK(emulator.up());
  auto module = OpenOrFail(emulator.Config());
  aio::ModbusAioModule& m = *module;
  uint32_t read[4];
  m.inputs().ReadAll(read, 4);
  LONGS_EQUAL(2048, read[0]);
  CHECK(m.last_error().empty());
  const uint32_t counts[4] = {100, 100, 100, 100};

  emulator.Pause();  // silent, like a pulled cable: each transfer ends at the response timeout
  const auto paused = Clock::now();
  CHECK(m.outputs().WriteAll(counts, 4) != palpa::hal::AnalogOutput::kAllWritten);
  std::printf(
      "\n  a silent module's write failed after %lld ms (response timeout %d ms)\n",
      static_cast<long long>(
          std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - paused).count()),
      emulator.Config().response_timeout_ms);
  CHECK_TEXT(m.last_error().find("timed out") != std::string::npos, m.last_error().c_str());
  m.inputs().ReadAll(read, 4);
  for (uint32_t r : read) LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, r);
  CHECK(!m.inputs().Read(0).ok());
  CHECK(m.outputs().Write(0, 1) == Status::kTimeout);

  emulator.Stop();  // gone: refused at once, still an error
  CHECK(m.outputs().WriteAll(counts, 4) != palpa::hal::AnalogOutput::kAllWritten);
  m.inputs().ReadAll(read, 4);
  for (uint32_t r : read) LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, r);
  CHECK_TEXT(m.last_error().find("127.0.0.1") != std::string::npos, m.last_error().c_str());
  CHECK(m.failures() >= 6);
}

TEST(ModbusAio, AModuleThatIsNotThereOrNotAnEk9000IsRefusedAtStart) {
  aio::ModbusAioConfig config;
  config.port = palpa::testing::FreeTcpPort();  // nothing listens there
  auto refused = aio::ModbusAioModule::Open(config);
  CHECK(refused.value == nullptr && refused.status == Status::kIoError);
  std::string error = refused.message;
  const std::string where = "tcp:127.0.0.1:" + std::to_string(config.port) + " unit 1: ";
  CHECK_TEXT(error.rfind(where + "connecting: ", 0) == 0, error.c_str());
  // A Modbus server with another register map (the calibration tests' rig): no watchdog there.
  const pid_t other = fork();
  if (other == 0) {
    execl("/usr/bin/python3", "python3", PALPA_SOURCE_DIR "/tests/calibration/pymodbus_rig.py",
          std::to_string(config.port).c_str(), "/dev/null", nullptr);
    _exit(127);
  }
  palpa::testing::ChildProcess other_server(other, SIGKILL);
  CHECK(WaitUntil(
      [&] {
        refused = aio::ModbusAioModule::Open(config);
        error = refused.message;
        return refused.value == nullptr && error.find("connecting") == std::string::npos;
      },
      10));
  other_server.Stop();
  STRCMP_EQUAL((where + "writing 1 at 0x1120: Illegal data address").c_str(), error.c_str());
  LONGS_EQUAL(static_cast<int>(Status::kIoError), static_cast<int>(refused.status));
}

TEST(ModbusAio, TheSameModuleOverRtu) {
  char dir_pattern[] = "/tmp/palpa-aio-rtu-XXXXXX";
  CHECK(mkdtemp(dir_pattern) != nullptr);
  const std::string dir = dir_pattern, module_end = dir + "/module", controller_end = dir + "/ctl";
  const pid_t socat = fork();  // a pty pair stands for the RS-485 line
  if (socat == 0) {
    execlp("socat", "socat", ("pty,raw,echo=0,link=" + module_end).c_str(),
           ("pty,raw,echo=0,link=" + controller_end).c_str(), nullptr);
    _exit(127);
  }
  palpa::testing::ChildProcess line(socat, SIGKILL);
  CHECK(WaitUntil([&] { return access(controller_end.c_str(), F_OK) == 0; }, 5));
  const pid_t emulator = fork();
  if (emulator == 0) {
    execl("/usr/bin/python3", "python3", PALPA_SOURCE_DIR "/tests/hal/linux/ek9000_emulator.py",
          ("rtu:" + module_end).c_str(), "2,4,6,8", nullptr);
    _exit(127);
  }
  palpa::testing::ChildProcess module_process(emulator, SIGKILL);
  aio::ModbusAioConfig config;
  config.tcp = false;
  config.host = controller_end;
  config.watchdog_ms = 5000;  // outlives the module object, so the probe below sees its writes
  config.response_timeout_ms = 200;
  std::unique_ptr<aio::ModbusAioModule> module;
  std::string error;
  CHECK(WaitUntil(
      [&] {
        auto opened = aio::ModbusAioModule::Open(config);
        error = opened.message;
        module = std::move(opened.value);
        return module != nullptr;
      },
      10));
  CHECK_TEXT(module != nullptr, error.c_str());
  const uint32_t counts[4] = {4095, 2048, 1, 0};
  LONGS_EQUAL(palpa::hal::AnalogOutput::kAllWritten, module->outputs().WriteAll(counts, 4));
  uint32_t read[4];
  module->inputs().ReadAll(read, 4);
  for (int i = 0; i < 4; ++i) DOUBLES_EQUAL((2.0 + 2 * i) / 10 * 4095, read[i], 1.0);
  module.reset();
  modbus_t* probe = modbus_new_rtu(controller_end.c_str(), 115200, 'N', 8, 1);
  modbus_set_slave(probe, 1);
  modbus_set_response_timeout(probe, 1, 0);
  CHECK(modbus_connect(probe) == 0);
  uint16_t held[4] = {};
  LONGS_EQUAL(4, modbus_read_registers(probe, 0x0800, 4, held));
  for (int i = 0; i < 4; ++i) LONGS_EQUAL(ExpectedCode(counts[i]), held[i]);
  LONGS_EQUAL(5000, [&] {
    uint16_t v = 0;
    modbus_read_registers(probe, 0x1120, 1, &v);
    return v;
  }());
  modbus_close(probe);
  modbus_free(probe);
  std::remove(module_end.c_str());
  std::remove(controller_end.c_str());
  rmdir(dir.c_str());
}
