// Configuration files as JSON: a round trip of every compiled-in configuration, and values the
// wire would refuse are refused with the field's path before anything trusts their range.
#include <stdexcept>
#include <string>

#include "palpa/core/board_configs.h"
#include "palpa/host/config_json.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace pc = palpa::core;
namespace ph = palpa::host;
using nlohmann::json;

namespace {

using palpa::testing::Contains;

/// The message ApplyConfigJson throws for the JSON text `patch` onto thesis-5finger ("" when it
/// applies).
std::string RefusalOf(const char* patch) {
  pc::BoardConfig config = *pc::FindBoardConfig("thesis-5finger");
  try {
    ph::ApplyConfigJson(json::parse(patch), config);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_GROUP(ConfigJson){};

TEST(ConfigJson, EveryCompiledConfigurationPrintsAndReadsBackUnchanged) {
  for (uint8_t i = 0; i < pc::kBoardConfigCount; ++i) {
    const pc::BoardConfig& original = *pc::kBoardConfigs[i].config;
    const json printed = ph::ConfigToJson(original);
    pc::BoardConfig read{};
    ph::ApplyConfigJson(printed, read);
    CHECK_TEXT(ph::ConfigToJson(read) == printed, pc::kBoardConfigs[i].name);
    LONGS_EQUAL(original.line_count, read.line_count);
    LONGS_EQUAL(original.finger_count, read.finger_count);
  }
}

TEST(ConfigJson, ValuesTheWireWouldRefuseAreRefusedWithTheirPath) {
  // adc_bits is 8..24 on the wire; 252 once reached validation, which shifts by it.
  std::string why = RefusalOf(R"({"lines": [{"line": 0, "adc_bits": 252}]})");
  CHECK_TEXT(Contains(why, "lines[0]") && Contains(why, "adc_bits") && Contains(why, "8 … 24"),
             why.c_str());
  why = RefusalOf(R"({"lines": [{"line": 1, "trim_kp": 1e300}]})");  // a float beyond float
  CHECK_TEXT(Contains(why, "lines[0]") && Contains(why, "trim_kp") && Contains(why, "finite"),
             why.c_str());
  why = RefusalOf(R"({"lines": [{"line": 1, "trim_kp": -0.5}]})");  // a negative gain
  CHECK_TEXT(Contains(why, "trim_kp") && Contains(why, "outside"), why.c_str());
  why = RefusalOf(R"({"board": {"host_timeout_us": -1}})");
  CHECK_TEXT(Contains(why, "board") && Contains(why, "host_timeout_us"), why.c_str());
  STRCMP_EQUAL("", RefusalOf(R"({"lines": [{"line": 1, "trim_kp": 0.2}]})").c_str());
}

TEST(ConfigJson, ARefusedFileChangesNothing) {
  pc::BoardConfig config = *pc::FindBoardConfig("thesis-5finger");
  const json before = ph::ConfigToJson(config);
  // The first line's change is fine; the second entry is refused: neither may be applied.
  const json patch = json::parse(
      R"({"lines": [{"line": 0, "slew_pa_per_s": 1000}, {"line": 1, "adc_bits": 99}]})");
  CHECK_THROWS(std::runtime_error, ph::ApplyConfigJson(patch, config));
  CHECK(ph::ConfigToJson(config) == before);
}

TEST(ConfigJson, UnknownSectionsAndFieldsAreRefused) {
  CHECK(Contains(RefusalOf(R"({"wires": []})"), "unknown section 'wires'"));
  CHECK(Contains(RefusalOf(R"({"lines": [{"line": 0, "slew": 1}]})"), "unknown field 'slew'"));
  CHECK(Contains(RefusalOf(R"({"lines": [{"line": 9}]})"), "line 9 does not exist"));
}
