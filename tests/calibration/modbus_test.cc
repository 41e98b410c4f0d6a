// Rig drivers: register maps (every bad field named), value encodings in every byte and word
// order, the Modbus drivers against palpa-sim's rig over TCP and over RTU on a socat pty pair and
// against an independent server (pymodbus), and the Net F/T driver against palpa-sim's RDT server.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "child_process.h"
#include "file_text.h"
#include "palpa/calibration/modbus_devices.h"
#include "palpa/calibration/rig_file.h"
#include "sim_process.h"
#include "wait_until.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;
using nlohmann::json;

namespace {

/// The shipped sim rig description with both devices pointed at `uri`.
cal::RigDescription SimRig(const std::string& uri) {
  json j = json::parse(pt::FileText(std::string(PALPA_SOURCE_DIR) + "/calibration/rigs/sim.json"));
  j["stage"]["address"] = uri;
  j["force_sensor"]["address"] = uri;
  const auto rig = cal::ParseRigDescription(j.dump());
  CHECK_TEXT(rig.ok(), rig.message.c_str());
  return rig.value;
}

/// "tcp:127.0.0.1:PORT" → "modbus-tcp://127.0.0.1:PORT/1".
std::string ModbusUri(const std::string& address) {
  return "modbus-tcp://" + address.substr(4) + "/1";
}

/// Short moves through the drivers: up, down into the vented film (a contact force), tare.
void ExerciseRig(cal::RigDevices& d) {
  CHECK(d.stage->MoveTo(1.0, 5.0).ok());
  bool moving = true;
  CHECK(pt::WaitUntil([&] { return d.stage->Moving(&moving).ok() && !moving; }, 5));
  double mm = 0;
  CHECK(d.stage->Position(&mm).ok());
  DOUBLES_EQUAL(1.0, mm, 0.002);
  double newtons = 1;
  CHECK(d.force->Tare().ok());
  CHECK(d.force->Read(&newtons).ok());
  DOUBLES_EQUAL(0, newtons, 0.01);
  CHECK(d.stage->MoveTo(-0.5, 5.0).ok());  // half a millimetre into the soft film
  CHECK(pt::WaitUntil([&] { return d.stage->Moving(&moving).ok() && !moving; }, 5));
  CHECK(d.force->Read(&newtons).ok());
  DOUBLES_EQUAL(0.15, newtons, 0.03);  // 0.3 N/mm contact
  CHECK(d.stage->MoveTo(3.0, 0.5).ok());
  CHECK(d.stage->Stop().ok());
  CHECK(d.stage->Moving(&moving).ok());
  CHECK(pt::WaitUntil([&] { return d.stage->Moving(&moving).ok() && !moving; }, 2));
  CHECK(d.stage->Position(&mm).ok());
  CHECK(mm < 0.0);  // stopped before it got anywhere
}

}  // namespace

TEST_GROUP(RegisterMap){};

TEST(RegisterMap, EveryBadFieldIsNamed) {
  const json good =
      json::parse(pt::FileText(std::string(PALPA_SOURCE_DIR) + "/calibration/rigs/sim.json"));
  struct Case {
    std::function<void(json&)> edit;
    const char* names;
  };
  const Case cases[] = {
      {[](json& j) { j["stage"]["registers"].erase("position"); },
       "stage.registers.position: missing"},
      {[](json& j) { j["stage"]["registers"]["target"]["table"] = "input"; },
       "stage.registers.target.table: input"},
      {[](json& j) { j["stage"]["registers"]["speed"]["type"] = "int64"; },
       "stage.registers.speed.type"},
      {[](json& j) { j["stage"]["registers"]["speed"]["scale"] = 0; },
       "stage.registers.speed.scale"},
      {[](json& j) { j["stage"]["address"] = "modbus://x"; }, "stage.address"},
      {[](json& j) { j["stage"]["commands"].erase("stop"); }, "stage.commands.stop: missing"},
      {[](json& j) { j["force_sensor"]["driver"] = "telepathy"; }, "force_sensor.driver"},
      {[](json& j) { j["force_sensor"]["commands"] = json::object(); },
       "force_sensor.commands.tare: missing"},
      {[](json& j) { j["limits"]["max_force_n"] = 500; }, "limits.max_force_n"},
      {[](json& j) { j["stage"]["word_order"] = "middle"; }, "stage.word_order"},
      {[](json& j) { j["colour"] = 1; }, "colour: unknown field"},
  };
  for (const Case& c : cases) {
    json j = good;
    c.edit(j);
    const auto parsed = cal::ParseRigDescription(j.dump());
    CHECK_FALSE(parsed.ok());
    CHECK_TEXT(parsed.message.find(c.names) != std::string::npos,
               (std::string(c.names) + " / " + parsed.message).c_str());
  }
  CHECK(cal::ParseRigDescription(good.dump()).ok());
  CHECK(cal::ParseModbusAddress("modbus-rtu:/dev/ttyUSB0?baud=19200&unit=3").value.baud == 19200);
  const auto bad = cal::ParseModbusAddress("modbus-tcp://h:70000/1");
  LONGS_EQUAL((int)palpa::protocol::Status::kInvalidArgument, (int)bad.status);
}

TEST(RegisterMap, ValuesRoundTripInEveryTypeAndOrder) {
  for (bool swap : {false, true}) {
    for (bool low_first : {false, true}) {
      cal::RegisterMap m;
      m.byte_swap = swap;
      m.low_word_first = low_first;
      for (auto type : {cal::RegisterType::kU16, cal::RegisterType::kI16, cal::RegisterType::kU32,
                        cal::RegisterType::kI32, cal::RegisterType::kF32}) {
        cal::Register r;
        r.type = type;
        r.scale = 0.001;
        const bool is_unsigned = type == cal::RegisterType::kU16 || type == cal::RegisterType::kU32;
        const double value = is_unsigned ? 12.345 : -12.345;
        const auto words = m.Encode(r, value);
        LONGS_EQUAL(r.words(), words.size());
        DOUBLES_EQUAL(value, m.Decode(r, words.data()), 1e-6);
      }
    }
  }
  cal::RegisterMap m;
  cal::Register r;
  r.type = cal::RegisterType::kI32;
  const auto words = m.Encode(r, 0x12345678);
  LONGS_EQUAL(0x1234, words[0]);  // Modbus default: high word first, big-endian bytes
  LONGS_EQUAL(0x5678, words[1]);
}

TEST_GROUP(ModbusRig){};

TEST(ModbusRig, DriversMoveTheSimulatedStageAndReadItsForceOverTcp) {
  pt::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0", "--rig-modbus",
                   "tcp:127.0.0.1:0", "--speed", "10"}));
  auto devices = cal::OpenRigDevices(SimRig(ModbusUri(sim.rig_address())));
  CHECK_TEXT(devices.ok(), devices.message.c_str());
  ExerciseRig(devices.value);
}

TEST(ModbusRig, TheForceCanComeFromASimulatedNetFtOverRdt) {
  pt::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0", "--rig-modbus",
                   "tcp:127.0.0.1:0", "--rig-netft", "udp:127.0.0.1:0", "--speed", "10"}));
  json j = json::parse(pt::FileText(std::string(PALPA_SOURCE_DIR) + "/calibration/rigs/sim.json"));
  j["stage"]["address"] = ModbusUri(sim.rig_address());
  j["force_sensor"] = {
      {"driver", "netft"}, {"address", "netft://" + sim.netft_address().substr(4)}, {"axis", "fz"}};
  const auto rig = cal::ParseRigDescription(j.dump());
  CHECK_TEXT(rig.ok(), rig.message.c_str());
  CHECK(rig.value.netft.has_value());
  auto devices = cal::OpenRigDevices(rig.value);
  CHECK_TEXT(devices.ok(), devices.message.c_str());
  ExerciseRig(devices.value);
  j["force_sensor"]["axis"] = "fw";
  const auto bad = cal::ParseRigDescription(j.dump());
  LONGS_EQUAL((int)palpa::protocol::Status::kInvalidArgument, (int)bad.status);
  CHECK(bad.message.find("force_sensor.axis") != std::string::npos);
}

TEST(ModbusRig, DriversWorkOverRtuOnAPtyPair) {
  char dir_pattern[] = "/tmp/palpa-rtu-XXXXXX";
  const std::string dir = mkdtemp(dir_pattern);
  const std::string a = dir + "/board", b = dir + "/host";
  const pid_t socat_pid = fork();
  if (socat_pid == 0) {
    execlp("socat", "socat", ("pty,raw,echo=0,link=" + a).c_str(),
           ("pty,raw,echo=0,link=" + b).c_str(), nullptr);
    _exit(127);
  }
  pt::ChildProcess socat(socat_pid);
  CHECK(pt::WaitUntil([&] { return access(a.c_str(), F_OK) == 0 && access(b.c_str(), F_OK) == 0; },
                      5));
  {
    pt::SimProcess sim;
    CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0", "--rig-modbus",
                     "rtu:" + a, "--speed", "10"}));
    auto devices = cal::OpenRigDevices(SimRig("modbus-rtu:" + b + "?baud=115200&unit=1"));
    CHECK_TEXT(devices.ok(), devices.message.c_str());
    ExerciseRig(devices.value);
  }
}

TEST(ModbusRig, DriversSpeakStandardModbusToAnIndependentServer) {
  const int port = palpa::testing::FreeTcpPort();
  char log_pattern[] = "/tmp/palpa-pymodbus-XXXXXX";
  const int log_fd = mkstemp(log_pattern);
  close(log_fd);
  const std::string log = log_pattern;
  const pid_t server_pid = fork();
  if (server_pid == 0) {
    execl("/usr/bin/python3", "python3", PALPA_SOURCE_DIR "/tests/calibration/pymodbus_rig.py",
          std::to_string(port).c_str(), log.c_str(), nullptr);
    _exit(127);
  }
  pt::ChildProcess server(server_pid);
  const json map = {
      {"address", "modbus-tcp://127.0.0.1:" + std::to_string(port) + "/1"},
      {"word_order", "little"},
      {"registers",
       {{"position", {{"table", "input"}, {"address", 100}, {"type", "int32"}, {"scale", 0.001}}},
        {"moving", {{"table", "input"}, {"address", 102}, {"type", "uint16"}}},
        {"target", {{"table", "holding"}, {"address", 110}, {"type", "int32"}, {"scale", 0.001}}},
        {"speed", {{"table", "holding"}, {"address", 112}, {"type", "uint16"}, {"scale", 0.001}}},
        {"command", {{"table", "holding"}, {"address", 113}, {"type", "uint16"}}}}},
      {"commands", {{"move", 5}, {"stop", 6}}}};
  json force = {
      {"address", "modbus-tcp://127.0.0.1:" + std::to_string(port) + "/1"},
      {"byte_order", "little"},
      {"registers", {{"force", {{"table", "input"}, {"address", 200}, {"type", "float32"}}}}}};
  const auto stage_map = cal::ParseRegisterMap(map, "stage", cal::kStageRegisters);
  const auto force_map = cal::ParseRegisterMap(force, "force_sensor", cal::kForceRegisters);
  CHECK_TEXT(stage_map.ok() && force_map.ok(), (stage_map.message + force_map.message).c_str());
  std::unique_ptr<cal::ModbusDevice> stage_device, force_device;
  CHECK(pt::WaitUntil(
      [&] { return (stage_device = cal::ModbusDevice::Open(stage_map.value).value) != nullptr; },
      10));
  auto force_opened = cal::ModbusDevice::Open(force_map.value);
  CHECK_TEXT(force_opened.ok(), force_opened.message.c_str());
  force_device = std::move(force_opened.value);
  cal::ModbusStage stage(std::move(stage_device));
  cal::ModbusForceSensor sensor(std::move(force_device));
  double mm = 0, newtons = 0;
  bool moving = false;
  CHECK(stage.Position(&mm).ok());
  DOUBLES_EQUAL(12.345, mm, 1e-9);
  CHECK(stage.Moving(&moving).ok() && moving);
  CHECK(sensor.Read(&newtons).ok());
  DOUBLES_EQUAL(1.5, newtons, 1e-9);
  CHECK(sensor.Tare().ok());  // no tare register: an offset kept by the driver
  CHECK(sensor.Read(&newtons).ok());
  DOUBLES_EQUAL(0, newtons, 1e-9);
  CHECK(stage.MoveTo(7.5, 0.25).ok());
  server.Stop();
  const std::string written = pt::FileText(log);
  // Speed first (250 µm/s), then the target low word first (7500, 0), then the move command.
  CHECK_TEXT(written.find("write 112 250\nwrite 110 7500 0\nwrite 113 5\n") != std::string::npos,
             written.c_str());
}
