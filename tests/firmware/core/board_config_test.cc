// Configuration validation, hard ceilings, the blob encoding and the compiled-in configurations.
#include <cstring>
#include <string>
#include <vector>

#include "palpa/core/board_configs.h"
#include "palpa/core/ceilings.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

namespace {

pc::BoardConfig Thesis5() { return *pc::FindBoardConfig("thesis-5finger"); }

pp::Status Validate(const pc::BoardConfig& c, pc::ConfigError* e = nullptr) {
  pc::ConfigError ignored;
  return pc::ValidateConfig(c, e != nullptr ? e : &ignored);
}

}  // namespace

TEST_GROUP(BoardConfigs){};

TEST(BoardConfigs, EveryCompiledConfigurationIsValid) {
  LONGS_EQUAL(4, pc::kBoardConfigCount);
  for (uint8_t i = 0; i < pc::kBoardConfigCount; ++i) {
    pc::ConfigError e;
    const pp::Status s = pc::ValidateConfig(*pc::kBoardConfigs[i].config, &e);
    CHECK_TEXT(s == pp::Status::kOk,
               (std::string(pc::kBoardConfigs[i].name) + ": " + e.reason).c_str());
    STRCMP_EQUAL(pc::kBoardConfigs[i].name, pc::kBoardConfigs[i].config->board.config_name.data());
  }
}

TEST(BoardConfigs, LayoutsMatchTheThesisSystems) {
  const pc::BoardConfig* p3 = pc::FindBoardConfig("thesis-pneumatic-3");
  LONGS_EQUAL(3, p3->line_count);
  LONGS_EQUAL(3, p3->finger_count);
  const pc::BoardConfig* j2 = pc::FindBoardConfig("thesis-jamming-2");
  LONGS_EQUAL(4, j2->line_count);
  CHECK(j2->fingers[1].kind == pp::FingerKind::kJamming);
  LONGS_EQUAL(20000, j2->fingers[1].bias_pa);
  const pc::BoardConfig t5 = Thesis5();
  LONGS_EQUAL(7, t5.line_count);
  LONGS_EQUAL(5, t5.finger_count);
  LONGS_EQUAL(4, t5.fingers[4].line_a);
  LONGS_EQUAL(6, t5.fingers[4].line_b);
  CHECK(t5.lines[6].kind == pp::LineKind::kVacuum);
  const pc::BoardConfig* f8 = pc::FindBoardConfig("full-8");
  LONGS_EQUAL(8, f8->line_count);
  LONGS_EQUAL(4, f8->finger_count);
  CHECK(pc::FindBoardConfig("no-such-board") == nullptr);
}

TEST_GROUP(ConfigValidation){};

TEST(ConfigValidation, NothingBeyondTheHardCeilings) {
  auto c = Thesis5();
  c.lines[0].limit_max_pa = 100001;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
  c = Thesis5();
  c.lines[3].limit_max_pa = 25000;  // bias ceiling is 20 kPa
  c.lines[3].command_max_pa = 100000;
  pc::ConfigError e;
  CHECK(Validate(c, &e) == pp::Status::kOutOfRange);
  LONGS_EQUAL(3, e.index);
  CHECK(e.section == pp::ConfigSection::kLine);
  c = Thesis5();
  c.lines[5].limit_min_pa = -100001;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
  c = Thesis5();
  c.lines[5].limit_max_pa = 1000;  // a vacuum line never goes positive
  CHECK(Validate(c) == pp::Status::kOutOfRange);
}

TEST(ConfigValidation, SafeValueMustBeWithinTheLimits) {
  auto c = Thesis5();
  c.lines[1].limit_min_pa = 5000;
  CHECK(Validate(c) == pp::Status::kOutOfRange);  // safe 0 Pa is now outside
}

TEST(ConfigValidation, LimitsThatLeaveZeroOutMustClearTheRegulatorMinimum) {
  // Below regulator_min_pa (1 kPa) a line commands 0 Pa: limits from 129 Pa up would be left.
  auto c = Thesis5();
  c.lines[0].limit_min_pa = 129;
  c.lines[0].safe_pa = 185;
  pc::ConfigError e;
  CHECK(Validate(c, &e) == pp::Status::kOutOfRange);
  STRCMP_CONTAINS("regulator's minimum", e.reason);
  c.lines[0].limit_min_pa = 1000;  // from the minimum up: 0 Pa is never commanded
  c.lines[0].safe_pa = 1000;
  CHECK(Validate(c) == pp::Status::kOk);
  pp::ConfigureLine vacuum = Thesis5().lines[5];  // the same for a vacuum line, mirrored
  vacuum.limit_max_pa = vacuum.safe_pa = -500;
  CHECK(pc::ValidateLine(vacuum, &e) == pp::Status::kOutOfRange);
  vacuum.limit_max_pa = vacuum.safe_pa = -1000;
  CHECK(pc::ValidateLine(vacuum, &e) == pp::Status::kOk);
}

TEST(ConfigValidation, TrimGainsStayBelowTheCrossover) {
  auto c = Thesis5();
  c.lines[0].trim_ki_per_s = 7.0f;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
  c = Thesis5();
  c.lines[0].trim_authority_pa = 20000;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
}

TEST(ConfigValidation, CorrectionAndInverseMustBeMonotone) {
  auto c = Thesis5();
  c.lines[0].correction_count = 3;
  c.lines[0].correction[0] = {0, 0, 0};
  c.lines[0].correction[1] = {50000, 60000, 50000};
  c.lines[0].correction[2] = {100000, 55000, 100000};  // rising branch turns back
  CHECK(Validate(c) == pp::Status::kBadValue);
  c = Thesis5();
  c.fingers[0].inverse[2].output = c.fingers[0].inverse[1].output;  // repeated output
  CHECK(Validate(c) == pp::Status::kBadValue);
  c = Thesis5();
  c.fingers[0].inverse[4].setpoint_pa = 110000;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
}

TEST(ConfigValidation, FingersNeedTheRightLines) {
  auto c = Thesis5();
  c.fingers[0].line_a = 3;  // a bias line for a pneumatic finger
  CHECK(Validate(c) == pp::Status::kBadValue);
  c = Thesis5();
  c.fingers[3].line_b = 2;  // a pressure line as vacuum
  CHECK(Validate(c) == pp::Status::kBadValue);
  c = Thesis5();
  c.fingers[1].line_a = 0;  // two fingers on one line
  CHECK(Validate(c) == pp::Status::kBadValue);
  c = Thesis5();
  c.fingers[3].bias_pa = 30000;
  CHECK(Validate(c) == pp::Status::kOutOfRange);
  c = Thesis5();
  c.fingers[0].compensator = pp::CompensatorKind::kPrandtlIshlinskii;  // with no parameters
  CHECK(Validate(c) == pp::Status::kBadValue);
}

TEST(ConfigValidation, TelemetryBatchMustFitAFrame) {
  auto c = Thesis5();
  c.board.telemetry_batch = 3;  // 3 ticks x 7 lines = 21 samples > 19
  CHECK(Validate(c) == pp::Status::kOutOfRange);
}

TEST_GROUP(ConfigBlob){};

TEST(ConfigBlob, RoundTripsEveryConfigurationAndItsCrc) {
  for (uint8_t i = 0; i < pc::kBoardConfigCount; ++i) {
    const pc::BoardConfig& original = *pc::kBoardConfigs[i].config;
    std::vector<uint8_t> blob(pc::kMaxConfigBlob);
    const auto n = pc::EncodeConfigBlob(original, blob.data(), blob.size());
    CHECK(n.ok());
    pc::BoardConfig back{};
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)pc::ApplyConfigBlob(blob.data(), n.value, back, nullptr));
    LONGS_EQUAL(pc::ConfigCrc(original), pc::ConfigCrc(back));
    LONGS_EQUAL(original.finger_count, back.finger_count);
  }
  CHECK(pc::ConfigCrc(*pc::kBoardConfigs[0].config) != pc::ConfigCrc(*pc::kBoardConfigs[1].config));
}

TEST(ConfigBlob, BadRecordsAreNamed) {
  std::vector<uint8_t> blob(pc::kMaxConfigBlob);
  const auto n = pc::EncodeConfigBlob(Thesis5(), blob.data(), blob.size());
  pc::BoardConfig back{};
  pc::ConfigError e;
  LONGS_EQUAL((int)pp::Status::kBadLength,
              (int)pc::ApplyConfigBlob(blob.data(), n.value - 1, back, &e));
  blob[2] = 0x21;  // the first record claims to be a setpoint message
  LONGS_EQUAL((int)pp::Status::kUnsupported,
              (int)pc::ApplyConfigBlob(blob.data(), n.value, back, &e));
}
