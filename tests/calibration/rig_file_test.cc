// Rig files and journals that try to hurt the calibration: numbers JSON cannot hold, values of
// the wrong type where a driver name or a number belongs, addresses with endless digits, and
// journals damaged between runs — each refused naming the field, never thrown out of the parser.
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/rig_file.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
using nlohmann::json;

namespace {

const char kRig[] = R"({
  "name": "lab",
  "stage": {"driver": "modbus", "address": "modbus-tcp://127.0.0.1:1502/1",
            "registers": {"position": {"table": "input", "address": 0, "type": "int32"},
                          "moving": {"table": "input", "address": 2, "type": "uint16"},
                          "target": {"table": "holding", "address": 10, "type": "int32"},
                          "speed": {"table": "holding", "address": 12, "type": "uint16"},
                          "command": {"table": "holding", "address": 13, "type": "uint16"}},
            "commands": {"move": 1, "stop": 2}},
  "force_sensor": {"driver": "netft", "address": "netft://127.0.0.1:49152"},
  "force_noise_n": 0.0017
})";

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  CHECK_TEXT(at != std::string::npos, from.c_str());
  return text.replace(at, from.size(), to);
}

/// The error a rig text is refused with ("" when it is accepted).
std::string RigError(const std::string& text) {
  const auto rig = cal::ParseRigDescription(text);
  if (rig.ok()) return "";
  if (rig.status != palpa::protocol::Status::kInvalidArgument)
    return "(refused with another status)";
  return rig.message.empty() ? "(refused without a reason)" : rig.message;
}

}  // namespace

TEST_GROUP(HostileRigFiles){};

TEST(HostileRigFiles, EveryBadValueIsRefusedNamingItsField) {
  CHECK_EQUAL(std::string(), RigError(kRig));
  struct Case {
    const char* from;
    const char* to;
    const char* names;
  };
  const Case cases[] = {
      {"\"force_noise_n\": 0.0017", "\"force_noise_n\": 1e400", "force_noise_n: "},
      {"\"force_noise_n\": 0.0017", "\"force_noise_n\": \"low\"", "force_noise_n: must be a"},
      {"\"driver\": \"modbus\"", "\"driver\": 5", "stage.driver: must be"},
      {"\"driver\": \"netft\"", "\"driver\": [1]", "force_sensor.driver"},
      {"127.0.0.1:1502/1", "127.0.0.1:99999999999999999999/1", "stage.address: "},
      {"127.0.0.1:1502/1", "127.0.0.1:1502/99999999999999999999", "stage.address: "},
      {"127.0.0.1:49152", "127.0.0.1:99999999999999999999", "force_sensor.address: "},
      {"\"address\": 10", "\"address\": 1e400", "stage.registers.target.address: "},
      {"\"name\": \"lab\"", "\"name\": \"lab\", \"limits\": 1", "limits: must be an object"},
  };
  for (const Case& c : cases) {
    const std::string error = RigError(Replaced(kRig, c.from, c.to));
    CHECK_TEXT(error.find(c.names) != std::string::npos,
               (std::string(c.names) + " / " + error).c_str());
    CHECK_TEXT(error.find("[json.exception") == std::string::npos, error.c_str());
  }
}

TEST(HostileRigFiles, TheFileIsNamedAndItsLimitsKept) {
  const std::string path = "/tmp/palpa-rig-" + std::to_string(getpid()) + ".json";
  std::ofstream(path) << Replaced(kRig, "\"force_noise_n\": 0.0017", "\"force_noise_n\": 1e400");
  auto loaded = cal::LoadRigDescription(path);
  CHECK_FALSE(loaded.ok());
  CHECK_TEXT(loaded.message.find(path + ": force_noise_n: ") != std::string::npos,
             loaded.message.c_str());
  std::ofstream(path) << std::string(1 << 20, ' ') << kRig;
  loaded = cal::LoadRigDescription(path);
  CHECK_FALSE(loaded.ok());
  CHECK_TEXT(loaded.message.find(path + ": larger than the") != std::string::npos,
             loaded.message.c_str());
  std::remove(path.c_str());
}

TEST_GROUP(HostileJournals){};

TEST(HostileJournals, ADamagedJournalIsRefusedNamingTheField) {
  const json good = {{"rig_time_s", 12.5},
                     {"corrections", {{"0", {{0, 0, 0}, {50000, 50600, 49500}}}}},
                     {"sweep", {{0, 0}, {10000, 300}}},
                     {"map", {{"grid_done", 1}, {"presses", json::array()}}}};
  const auto accepted = cal::ParseJournal(good.dump());
  CHECK_TEXT(accepted.ok(), accepted.message.c_str());
  struct Case {
    json::json_pointer where;
    json value;
    const char* names;
  };
  const Case cases[] = {
      {json::json_pointer("/sweep/1/0"), "x", "sweep[1][0]: must be a number"},
      {json::json_pointer("/sweep/1"), 3, "sweep[1]: must be an array"},
      {json::json_pointer("/corrections/0/1/2"), 1e12, "corrections.0[1][2]: "},
      {json::json_pointer("/corrections/9"), json::array(), "corrections.9: "},
      {json::json_pointer("/map/grid_done"), -1, "map.grid_done: "},
      {json::json_pointer("/map/presses"), json::array({json::array({1, 2})}), "map.presses[0]: "},
      {json::json_pointer("/rig_time_s"), "long", "rig_time_s: must be a number"},
      {json::json_pointer("/colour"), 1, "colour: unknown field"},
  };
  for (const Case& c : cases) {
    json j = good;
    j[c.where] = c.value;
    const auto refused = cal::ParseJournal(j.dump());
    CHECK_FALSE(refused.ok());
    CHECK_TEXT(refused.message.find(c.names) != std::string::npos,
               (std::string(c.names) + " / " + refused.message).c_str());
  }
  const auto huge = cal::ParseJournal("{\"rig_time_s\": 1e400}");
  CHECK_FALSE(huge.ok());
  CHECK_TEXT(huge.message.find("rig_time_s: ") != std::string::npos, huge.message.c_str());
}
