// The core's supervisor on the Modbus module: an outage latches faults, the board holds safe.
#include <modbus.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <memory>
#include <string>

#include "CppUTest/TestHarness.h"
#include "mini_client.h"
#include "palpa/core/board.h"
#include "palpa/core/board_configs.h"
#include "palpa/hal/fake/fakes.h"
#include "palpa/hal/linux/modbus_aio.h"

namespace aio = palpa::hal::linux_aio;
namespace fake = palpa::hal::fake;
namespace pc = palpa::core;
using palpa::protocol::Fault;
using palpa::protocol::FaultBit;

TEST_GROUP(ModbusAioBoard){};

TEST(ModbusAioBoard, AModuleOutageLatchesOutputAndSensorFaults) {
  const int port = palpa::testing::FreeTcpPort();
  const pid_t emulator = fork();
  if (emulator == 0) {  // eight inputs at 1 V: the thesis sensors' zero (1638 of 14 bits)
    execl("/usr/bin/python3", "python3", PALPA_SOURCE_DIR "/tests/hal/linux/ek9000_emulator.py",
          std::to_string(port).c_str(), "1,1,1,1,1,1,1,1", nullptr);
    _exit(127);
  }
  struct Reaper {
    pid_t pid;
    ~Reaper() { kill(pid, SIGKILL), waitpid(pid, nullptr, 0); }
  } reaper{emulator};
  aio::ModbusAioConfig config;
  config.port = port;
  config.output_count = config.input_count = 8;
  config.input_bits = 14;
  config.response_timeout_ms = 50;
  std::unique_ptr<aio::ModbusAioModule> module;
  std::string error;
  for (int i = 0; i < 500 && module == nullptr; ++i) {
    module = aio::ModbusAioModule::Open(config, &error);
    if (module == nullptr) usleep(20000);
  }
  CHECK_TEXT(module != nullptr, error.c_str());

  const pc::BoardConfig* board_config = pc::FindBoardConfig("thesis-5finger");
  fake::FakeClock clock;
  fake::FakeDigitalOutput supply, dump, pump;
  fake::FakeByteLink link;
  pc::BoardIo io{
      clock,  module->outputs(), &module->inputs(), supply, dump, pump, nullptr, link, nullptr, 0,
      nullptr};
  clock.now_us = 1000000;
  pc::Board board(*board_config, io, pc::BoardIdentity{});
  board.Start();
  auto run = [&](int ticks) {
    for (int i = 0; i < ticks; ++i) {
      clock.now_us += pc::Board::kTickUs;
      board.Step();
    }
  };
  run(20);
  LONGS_EQUAL(0, board.latched_faults());
  kill(emulator, SIGSTOP);  // the module falls silent
  run(2);
  CHECK(board.latched_faults() & FaultBit(Fault::kOutputWrite));
  CHECK(board.latched_faults() & FaultBit(Fault::kImplausibleSensor));
  CHECK(board.safe());
  CHECK(!module->last_error().empty());
}
