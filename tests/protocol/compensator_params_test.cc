// Compensator parameter layouts: what each kind writes where, reading it back, refused shapes.
#include <string>
#include <vector>

#include "palpa/protocol/compensator_params.h"
#include "palpa/protocol/messages_config.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;
using pp::CompensatorKind;

TEST_GROUP(CompensatorParams){};

TEST(CompensatorParams, PiIsOffsetW0ThenThresholdsThenWeights) {
  const float r[] = {100, 200, 300}, w[] = {0.1f, 0.2f, 0.3f};
  pp::PlayParamSet set;
  set.operators = 3;
  set.offset = 5;
  set.w0 = 0.5f;
  set.thresholds = r;
  set.weights = w;
  float out[16];
  LONGS_EQUAL(8, pp::WritePlayParams(CompensatorKind::kPrandtlIshlinskii, set, out, 16));
  const std::vector<float> expected{5, 0.5f, 100, 200, 300, 0.1f, 0.2f, 0.3f};
  CHECK(std::vector<float>(out, out + 8) == expected);
  pp::PlayParamSet back;
  CHECK(pp::ReadPlayParams(CompensatorKind::kPrandtlIshlinskii, out, 8, back) == nullptr);
  LONGS_EQUAL(3, back.operators);
  LONGS_EQUAL(0, back.dead_zones);
  DOUBLES_EQUAL(5, back.offset, 0);
  DOUBLES_EQUAL(0.5, back.w0, 0);
  DOUBLES_EQUAL(300, back.thresholds[2], 0);
  DOUBLES_EQUAL(0.1, back.weights[0], 1e-7);
}

TEST(CompensatorParams, ApiLeadsWithTheOperatorCountAndEndsWithDeadZonesAndGains) {
  const float r[] = {100, 200}, w[] = {0.1f, 0.2f}, d[] = {10, 20, 30}, g[] = {1, 2, 3};
  pp::PlayParamSet set{2, 3, 5, 0.5f, r, w, d, g};
  std::vector<float> out(pp::PlayParamCount(CompensatorKind::kAsymmetricPi, 2, 3));
  LONGS_EQUAL(13, out.size());
  LONGS_EQUAL(13, pp::WritePlayParams(CompensatorKind::kAsymmetricPi, set, out.data(), 13));
  const std::vector<float> expected{2, 5, 0.5f, 100, 200, 0.1f, 0.2f, 10, 20, 30, 1, 2, 3};
  CHECK(out == expected);
  pp::PlayParamSet back;
  CHECK(pp::ReadPlayParams(CompensatorKind::kAsymmetricPi, out.data(), 13, back) == nullptr);
  LONGS_EQUAL(2, back.operators);
  LONGS_EQUAL(3, back.dead_zones);
  DOUBLES_EQUAL(30, back.dead_zone_thresholds[2], 0);
  DOUBLES_EQUAL(1, back.dead_zone_gains[0], 0);
}

TEST(CompensatorParams, BranchIsBandDeadBandThenOutputsRisingFalling) {
  const float y[] = {1, 2}, up[] = {10, 20}, down[] = {5, 15};
  const pp::BranchParamSet set{2, 300, 50, y, up, down};
  float out[8];
  LONGS_EQUAL(8, pp::WriteBranchParams(set, out, 8));
  const std::vector<float> expected{300, 50, 1, 2, 10, 20, 5, 15};
  CHECK(std::vector<float>(out, out + 8) == expected);
  pp::BranchParamSet back;
  CHECK(pp::ReadBranchParams(out, 8, back) == nullptr);
  LONGS_EQUAL(2, back.points);
  DOUBLES_EQUAL(15, back.falling[1], 0);
}

TEST(CompensatorParams, ASetThatDoesNotFitIsNotWritten) {
  const float r[1] = {1}, w[1] = {1};
  pp::PlayParamSet set;
  set.operators = 1;
  set.thresholds = r;
  set.weights = w;
  float out[3];
  LONGS_EQUAL(0, pp::WritePlayParams(CompensatorKind::kPrandtlIshlinskii, set, out, 3));
}

TEST(CompensatorParams, ShapesThatAreNotALayoutAreRefusedWithTheirReason) {
  float p[pp::kMaxCompensatorParams] = {};
  pp::PlayParamSet play;
  pp::BranchParamSet branch;
  STRCMP_EQUAL("pi parameters: need offset, w0 and n thresholds and weights",
               pp::ReadPlayParams(CompensatorKind::kPrandtlIshlinskii, p, 5, play));
  STRCMP_EQUAL("too many play operators (max 32)",
               pp::ReadPlayParams(CompensatorKind::kPrandtlIshlinskii, p, 68, play));
  STRCMP_EQUAL("api parameters: missing the operator count",
               pp::ReadPlayParams(CompensatorKind::kAsymmetricPi, p, 0, play));
  p[0] = 2.5f;
  STRCMP_EQUAL("api parameters: operator count not an integer in 1..32",
               pp::ReadPlayParams(CompensatorKind::kAsymmetricPi, p, 9, play));
  p[0] = 2;
  STRCMP_EQUAL("api parameters: need n, offset, w0, n thresholds and weights, dead zones and gains",
               pp::ReadPlayParams(CompensatorKind::kAsymmetricPi, p, 8, play));
  STRCMP_EQUAL("too many dead zones (max 8)",
               pp::ReadPlayParams(CompensatorKind::kAsymmetricPi, p, 7 + 18, play));
  STRCMP_EQUAL("branch parameters: need band, dead band and K outputs, rising and falling drives",
               pp::ReadBranchParams(p, 7, branch));
  STRCMP_EQUAL("too many branch points (max 24)", pp::ReadBranchParams(p, 2 + 3 * 25, branch));
}
