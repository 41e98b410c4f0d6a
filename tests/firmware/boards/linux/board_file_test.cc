// palpa-linux-board's configuration file: a full file read, and each refusal naming its field.
#include <filesystem>
#include <fstream>
#include <string>

#include "CppUTest/TestHarness.h"
#include "board_file.h"
#include "palpa/core/board_configs.h"
#include "temp_dir.h"

namespace lb = palpa::linux_board;

namespace {

std::string Refusal(const std::string& text) {
  const auto f = lb::ParseBoardFile(text);
  CHECK_TEXT(!f.ok(), ("accepted: " + text).c_str());
  // A file that is wrong, whichever parser found it (the module's included).
  LONGS_EQUAL(static_cast<int>(palpa::protocol::Status::kBadValue), static_cast<int>(f.status));
  return f.message;
}

// A module that fits thesis-5finger (seven lines, 14-bit sensors), with `extra` fields added.
std::string File(const std::string& extra) {
  return R"({"board": "thesis-5finger", "analog_module": {"outputs": {"count": 8},
            "inputs": {"count": 8, "bits": 14}})" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

}  // namespace

TEST_GROUP(BoardFile){};

TEST(BoardFile, AFullFileIsReadFieldByField) {
  const auto parsed = lb::ParseBoardFile(
      File(R"("board_id": 7, "link": {"listen": "tty:/dev/ttyGS0", "baud": 921600},
      "gpio": {"supply_enable": "gpiochip0:17", "dump_enable": "gpiochip0:18",
               "pump_enable": "1:3", "valves": ["gpiochip0:5", "gpiochip0:6"],
               "estop": "gpiochip0:22", "estop_active": "low"},
      "watchdog": {"device": "/dev/watchdog0", "timeout_s": 2}, "realtime": {"priority": 70})"));
  CHECK_TEXT(parsed.ok(), parsed.message.c_str());
  const lb::BoardFile* f = &parsed.value;
  CHECK(f->config == palpa::core::FindBoardConfig("thesis-5finger"));
  LONGS_EQUAL(7, f->board_id);
  STRCMP_EQUAL("tty:/dev/ttyGS0", f->listen.c_str());
  LONGS_EQUAL(921600, f->baud);
  LONGS_EQUAL(8, f->module.output_count);
  LONGS_EQUAL(14, f->module.input_bits);
  STRCMP_EQUAL("gpiochip0:17", f->supply_enable.c_str());
  STRCMP_EQUAL("gpiochip0:18", f->dump_enable.c_str());
  STRCMP_EQUAL("1:3", f->pump_enable.c_str());
  LONGS_EQUAL(2, f->valves.size());
  STRCMP_EQUAL("gpiochip0:6", f->valves[1].c_str());
  STRCMP_EQUAL("gpiochip0:22", f->estop.c_str());
  CHECK(!f->estop_active_high);
  STRCMP_EQUAL("/dev/watchdog0", f->watchdog.c_str());
  LONGS_EQUAL(2, f->watchdog_timeout_s);
  LONGS_EQUAL(70, f->rt_priority);
  // Nothing but the module: no GPIO lines, no watchdog (the host tests' board).
  const auto bare = lb::ParseBoardFile(File(""));
  CHECK_TEXT(bare.ok(), bare.message.c_str());
  CHECK(bare.value.valves.empty() && bare.value.estop.empty() && bare.value.watchdog.empty());
  // The USB gadget link, on the first device controller or a named one.
  for (const char* usb : {"usb", "usb:dummy_udc.0"}) {
    const auto g = lb::ParseBoardFile(File(std::string(R"("link": {"listen": ")") + usb + "\"}"));
    CHECK_TEXT(g.ok(), g.message.c_str());
    STRCMP_EQUAL(usb, g.value.listen.c_str());
  }
}

TEST(BoardFile, EachRefusalNamesItsField) {
  const std::pair<std::string, const char*> cases[] = {
      {"[]", "not a JSON object"},
      {File(R"("colour": 1)"), "colour: unknown field"},
      {R"({"board": "nine-fingers", "analog_module": {}})", "board: unknown board configuration"},
      {R"({"board": "thesis-5finger"})", "analog_module: required"},
      {File(R"("link": {"listen": "udp:1"})"), "link.listen: expected tcp:HOST:PORT"},
      {File(R"("link": {"listen": "usbx"})"), "or usb:UDC"},
      {File(R"("link": {"baud": 12})"), "link.baud: expected an integer"},
      {File(R"("link": 5)"), "link: expected an object"},
      {File(R"("gpio": {"valves": ["gpiochip0:1", "gpiochip0"]})"),
       "gpio.valves[1]: expected CHIP:LINE"},
      {File(R"("gpio": {"pump_enable": "gpiochip0:x"})"), "gpio.pump_enable: expected CHIP:LINE"},
      {File(R"("gpio": {"supply_enable": "0:4", "estop": "0:4"})"),
       "gpio.estop: 0:4 is already used"},
      {File(R"("gpio": {"estop_active": "sideways"})"), "gpio.estop_active: expected high or low"},
      {File(R"("gpio": {"valves": ["0:1","0:2","0:3","0:4","0:5","0:6","0:7","0:8"]})"),
       "gpio.valves: 8 valves, but board thesis-5finger has 7 lines"},
      {File(R"("watchdog": {"timeout_s": 2})"), "watchdog.device: required"},
      {File(R"("watchdog": {"device": "/dev/watchdog", "timeout_s": 0})"), "watchdog.timeout_s"},
      {File(R"("realtime": {"priority": 100})"), "realtime.priority: expected an integer"},
      {R"({"analog_module": {"port": 0}})", "analog_module.port: expected an integer"},
      // The board's lines against the module (FitsTheModule, below, for the safe value).
      {R"({"analog_module": {"inputs": {"count": 8, "bits": 14}}})",
       "board: thesis-5finger has 7 lines, but analog_module.outputs.count is 4"},
      {R"({"analog_module": {"outputs": {"count": 8}, "inputs": {"count": 4, "bits": 14}}})",
       "board: thesis-5finger line 4: its sensor needs input 4, but analog_module.inputs.count is "
       "4"},
      {R"({"analog_module": {"outputs": {"count": 8}, "inputs": {"count": 8}}})",
       "line 0: a 14-bit sensor, but analog_module.inputs.bits is 12"},
      {R"({"analog_module": {"outputs": {"count": 8, "bits": 14}, "inputs": {"count": 8,
          "bits": 14}}})",
       "line 0: a 12-bit command, but analog_module.outputs.bits is 14"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string error = Refusal(text);
    CHECK_TEXT(error.find(expected) != std::string::npos,
               ("'" + error + "' does not say '" + expected + "'").c_str());
  }
}

TEST(BoardFile, ALineWhoseSafeValueIsNotZeroVoltsIsRefused) {
  palpa::hal::linux_aio::ModbusAioConfig module;
  module.output_count = module.input_count = 8;
  module.input_bits = 14;
  palpa::core::BoardConfig config = *palpa::core::FindBoardConfig("thesis-5finger");
  const palpa::hal::Done fits = lb::FitsTheModule(config, "thesis-5finger", module);
  CHECK_TEXT(fits.ok(), fits.message.c_str());
  config.lines[2].safe_pa = 20000;  // within its limits, but 2 V on the regulator's command
  const palpa::hal::Done refused = lb::FitsTheModule(config, "edited", module);
  CHECK(!refused.ok());
  // Where (the board, the line), what (the rule a host's change meets too, the value, its code).
  STRCMP_EQUAL(
      (std::string("board: edited line 2: ") + lb::SafeValueNotAtZeroVolts(config.lines[2]) +
       " (its safe value, 20000 Pa, is code 819)")
          .c_str(),
      refused.message.c_str());
  STRCMP_EQUAL(
      "safe value not commanded by 0 V: the module's fallback (0 V on every output) would not "
      "make the line safe",
      lb::SafeValueNotAtZeroVolts(config.lines[2]));
  CHECK(lb::SafeValueNotAtZeroVolts(palpa::core::FindBoardConfig("thesis-5finger")->lines[2]) ==
        nullptr);
  config = *palpa::core::FindBoardConfig("thesis-5finger");
  config.lines[1].dac_signal = palpa::protocol::SignalRange::kMilliamp4To20;
  const palpa::hal::Done signal = lb::FitsTheModule(config, "edited", module);
  CHECK_TEXT(signal.message.find("line 1: its command signal is 4-20mA") != std::string::npos,
             signal.message.c_str());
}

TEST(BoardFile, ALoadedFileIsNamedInItsRefusal) {
  const std::string dir = palpa::testing::MakeTempDir("palpa-board-file");
  const auto missing = lb::LoadBoardFile(dir + "/none.json");
  LONGS_EQUAL(static_cast<int>(palpa::protocol::Status::kIoError),
              static_cast<int>(missing.status));
  STRCMP_EQUAL((dir + "/none.json: cannot read").c_str(), missing.message.c_str());
  const std::string path = dir + "/board.json";
  std::ofstream(path) << File(R"("colour": 1)");
  const auto wrong = lb::LoadBoardFile(path);
  LONGS_EQUAL(static_cast<int>(palpa::protocol::Status::kBadValue), static_cast<int>(wrong.status));
  STRCMP_EQUAL((path + ": colour: unknown field").c_str(), wrong.message.c_str());
  std::ofstream(path) << File(R"("board_id": 3)");
  const auto right = lb::LoadBoardFile(path);
  CHECK_TEXT(right.ok(), right.message.c_str());
  LONGS_EQUAL(3, right.value.board_id);
  std::filesystem::remove_all(dir);
}
