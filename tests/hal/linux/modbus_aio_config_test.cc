// The Modbus analogue I/O module's configuration file: what it accepts, and each refusal's field.
#include <cstdio>
#include <string>

#include "CppUTest/TestHarness.h"
#include "palpa/hal/linux/modbus_aio_config.h"

namespace aio = palpa::hal::linux_aio;

namespace {

std::string Refusal(const std::string& text) {
  const auto c = aio::ParseModbusAioConfig(text);
  CHECK_TEXT(!c.ok(), ("accepted: " + text).c_str());
  CHECK(c.status == palpa::protocol::Status::kBadValue);
  return c.message;
}

}  // namespace

TEST_GROUP(ModbusAioConfig){};

TEST(ModbusAioConfig, ReadsEveryField) {
  const auto read_tcp = aio::ParseModbusAioConfig(
      R"({"analog_module": {"class": "beckhoff-ek9000", "transport": "tcp", "host": "10.0.0.5",
          "port": 5020, "unit": 3, "response_timeout_ms": 20, "watchdog_ms": 250,
          "outputs": {"count": 2, "bits": 15}, "inputs": {"count": 8, "bits": 14,
          "words_per_channel": 1}}})");
  CHECK_TEXT(read_tcp.ok(), read_tcp.message.c_str());
  const aio::ModbusAioConfig* tcp = &read_tcp.value;
  CHECK(tcp->tcp);
  STRCMP_EQUAL("tcp:10.0.0.5:5020 unit 3", tcp->Describe().c_str());
  LONGS_EQUAL(20, tcp->response_timeout_ms);
  LONGS_EQUAL(250, tcp->watchdog_ms);
  LONGS_EQUAL(2, tcp->output_count);
  LONGS_EQUAL(15, tcp->output_bits);
  LONGS_EQUAL(8, tcp->input_count);
  LONGS_EQUAL(14, tcp->input_bits);
  LONGS_EQUAL(1, tcp->input_words);
  const auto read_rtu = aio::ParseModbusAioConfig(
      R"({"analog_module": {"transport": "rtu", "device": "/dev/ttyUSB0", "baud": 19200,
          "parity": "E", "stop_bits": 1, "unit": 7}})");
  CHECK_TEXT(read_rtu.ok(), read_rtu.message.c_str());
  const aio::ModbusAioConfig* rtu = &read_rtu.value;
  CHECK(!rtu->tcp);
  LONGS_EQUAL('E', rtu->parity);
  LONGS_EQUAL(19200, rtu->baud);
  STRCMP_EQUAL("rtu:/dev/ttyUSB0 unit 7", rtu->Describe().c_str());
  LONGS_EQUAL(4, rtu->output_count);  // defaults: the EL4004's and EL3064's four channels
  LONGS_EQUAL(2, rtu->input_words);
}

TEST(ModbusAioConfig, EachRefusalNamesItsField) {
  const struct {
    const char* text;
    const char* error;
  } cases[] = {
      {"[1]", "not a JSON object"},
      {R"({"analog_module": {"port": 502}, "gpio": {}})", "(file).gpio: unknown field"},
      {R"({})", "analog_module: expected an object (the analogue I/O module)"},
      {R"({"analog_module": {"class": "adam-6024"}})",
       "analog_module.class: expected one of beckhoff-ek9000, not 'adam-6024'"},
      {R"({"analog_module": {"transport": 1}})",
       "analog_module.transport: expected one of tcp, rtu"},
      {R"({"analog_module": {"prot": 502}})", "analog_module.prot: unknown field"},
      {R"({"analog_module": {"port": 70000}})",
       "analog_module.port: expected an integer from 1 to 65535"},
      {R"({"analog_module": {"port": 502.5}})",
       "analog_module.port: expected an integer from 1 to 65535"},
      {R"({"analog_module": {"host": ""}})", "analog_module.host: expected a non-empty string"},
      {R"({"analog_module": {"baud": 9600}})",
       "analog_module.baud: not a field of transport 'tcp'"},
      {R"({"analog_module": {"transport": "rtu", "host": "x"}})",
       "analog_module.host: not a field of transport 'rtu'"},
      {R"({"analog_module": {"transport": "rtu"}})",
       "analog_module.device: required with transport 'rtu'"},
      {R"({"analog_module": {"transport": "rtu", "device": "/dev/ttyS0", "parity": "X"}})",
       "analog_module.parity: expected one of N, E, O, not 'X'"},
      {R"({"analog_module": {"transport": "rtu", "device": "/dev/ttyS0", "unit": 0}})",
       "analog_module.unit: expected an integer from 1 to 247"},
      {R"({"analog_module": {"watchdog_ms": 5}})",
       "analog_module.watchdog_ms: expected an integer from 10 to 60000"},
      {R"({"analog_module": {"watchdog_ms": 40, "response_timeout_ms": 40}})",
       "analog_module.watchdog_ms: must exceed response_timeout_ms, or one slow answer trips the "
       "module"},
      {R"({"analog_module": {"outputs": 4}})", "analog_module.outputs: expected an object"},
      {R"({"analog_module": {"outputs": {"count": 17}}})",
       "analog_module.outputs.count: expected an integer from 0 to 16"},
      {R"({"analog_module": {"outputs": {"bits": 16}}})",
       "analog_module.outputs.bits: expected an integer from 1 to 15"},
      {R"({"analog_module": {"inputs": {"words_per_channel": 3}}})",
       "analog_module.inputs.words_per_channel: expected an integer from 1 to 2"},
      {R"({"analog_module": {"inputs": {"stride": 2}}})",
       "analog_module.inputs.stride: unknown field"},
  };
  for (const auto& c : cases) STRCMP_EQUAL(c.error, Refusal(c.text).c_str());
}

TEST(ModbusAioConfig, AFileThatCannotBeReadIsNamed) {
  const auto missing = aio::LoadModbusAioConfig("/nonexistent/board.json");
  CHECK(!missing.ok());
  STRCMP_EQUAL("/nonexistent/board.json: cannot read", missing.message.c_str());
  char path[] = "/tmp/palpa-aio-XXXXXX";
  const int fd = mkstemp(path);
  CHECK(fd >= 0);
  const char text[] = R"({"analog_module": {"unit": 300}})";
  CHECK(write(fd, text, sizeof(text) - 1) == static_cast<ssize_t>(sizeof(text) - 1));
  close(fd);
  const auto refused = aio::LoadModbusAioConfig(path);
  CHECK(!refused.ok());
  STRCMP_EQUAL(
      (std::string(path) + ": analog_module.unit: expected an integer from 0 to 247").c_str(),
      refused.message.c_str());
  std::remove(path);
}
