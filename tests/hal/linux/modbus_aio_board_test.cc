// The core's supervisor on the Modbus module: an outage latches faults, the board holds safe.
#include <memory>
#include <string>

#include "CppUTest/TestHarness.h"
#include "ek9000_process.h"
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
  // Eight inputs at 1 V: the thesis sensors' zero (1638 of 14 bits).
  palpa::testing::Ek9000Emulator emulator("1,1,1,1,1,1,1,1");
  CHECK_TEXT(emulator.up(), emulator.output().c_str());
  aio::ModbusAioConfig config;
  config.port = emulator.port();
  config.output_count = config.input_count = 8;
  config.input_bits = 14;
  config.response_timeout_ms = 50;
  auto module_opened = aio::ModbusAioModule::Open(config);
  CHECK_TEXT(module_opened.ok(), module_opened.message.c_str());
  auto module = std::move(module_opened.value);

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
  emulator.Pause();  // the module falls silent
  run(2);
  CHECK(board.latched_faults() & FaultBit(Fault::kOutputWrite));
  CHECK(board.latched_faults() & FaultBit(Fault::kImplausibleSensor));
  CHECK(board.safe());
  CHECK(!module->last_error().empty());
}
