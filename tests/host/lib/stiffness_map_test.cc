// Levels, 0..1, N/mm, mm and kPa mapped per finger kind; refusals name what is wrong.
#include "palpa/host/stiffness_map.h"

#include <unistd.h>

#include <cstdio>
#include <string>

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

TEST_GROUP(StiffnessMap) {
  pp::FingerSummary pneumatic{pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, 0, pp::kNoLine};
  pp::FingerSummary jamming{pp::FingerKind::kJamming, pp::FingerMode::kTarget, 3, 5};
  ph::LevelTables levels = ph::LevelTables::Shipped();
  ph::FingerCurves curves;
  ph::Mapped Map(const pp::FingerSummary& f, ph::TargetKind k, double v,
                 ph::RangePolicy p = ph::RangePolicy::kRefuse) {
    return ph::MapRequest(f, levels, curves, ph::Request{k, v}, p);
  }
};

TEST(StiffnessMap, ShippedLevelTablesAreTheThesisOnes) {
  CHECK((levels.pneumatic_kpa == std::vector<double>{0, 10, 30}));
  CHECK((levels.jamming_kpa == std::vector<double>{0, -10, -100}));
  DOUBLES_EQUAL(20, levels.jamming_bias_kpa, 0);
  DOUBLES_EQUAL(-30, levels.jamming_alternative_middle_kpa, 0);
}

TEST(StiffnessMap, LevelsBecomeTargetsThroughTheNominalCurves) {
  LONGS_EQUAL(0, Map(pneumatic, ph::TargetKind::kLevel, 0).target);
  LONGS_EQUAL(248, Map(pneumatic, ph::TargetKind::kLevel, 1).target);   // 0.0458 * 10 - 0.2098 mm
  LONGS_EQUAL(1164, Map(pneumatic, ph::TargetKind::kLevel, 2).target);  // at 30 kPa
  LONGS_EQUAL(760, Map(jamming, ph::TargetKind::kLevel, 1).target);     // -10 kPa at 20 kPa bias
  LONGS_EQUAL(1300, Map(jamming, ph::TargetKind::kLevel, 2).target);
  CHECK(Map(jamming, ph::TargetKind::kLevel, 2).note.find("nominal thesis curves") !=
        std::string::npos);
  const ph::Mapped bad = Map(jamming, ph::TargetKind::kLevel, 3);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)bad.status);
  CHECK(bad.error.find("levels 0 … 2") != std::string::npos);
}

TEST(StiffnessMap, UnitsMustSuitTheFingerKind) {
  const ph::Mapped n = Map(pneumatic, ph::TargetKind::kStiffnessNPerMm, 1.0);
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)n.status);
  CHECK(n.error.find("pneumatic") != std::string::npos);
  LONGS_EQUAL((int)pp::Status::kBadValue,
              (int)Map(jamming, ph::TargetKind::kDeformationMm, 1.0).status);
  LONGS_EQUAL(1100, Map(jamming, ph::TargetKind::kStiffnessNPerMm, 1.1).target);
  LONGS_EQUAL(1200, Map(pneumatic, ph::TargetKind::kDeformationMm, 1.2).target);
}

TEST(StiffnessMap, OutsideTheCalibratedRangeIsRefusedOrClampedNeverExtrapolated) {
  const ph::Mapped refused = Map(jamming, ph::TargetKind::kStiffnessNPerMm, 1.5);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)refused.status);
  CHECK(refused.error.find("0.7 … 1.3") != std::string::npos);
  // Uncalibrated, the range is the nominal map's: Fig 5-36(c)'s axis, labelled as an assumption.
  CHECK(refused.error.find("axis range, an assumption") != std::string::npos);
  const ph::Mapped clamped =
      Map(jamming, ph::TargetKind::kStiffnessNPerMm, 1.5, ph::RangePolicy::kClamp);
  LONGS_EQUAL(1300, clamped.target);
  CHECK(clamped.note.find("clamped") != std::string::npos);
}

TEST(StiffnessMap, NormalizedAndRawPressure) {
  LONGS_EQUAL(0, Map(jamming, ph::TargetKind::kNormalized, 0).target);
  LONGS_EQUAL(1000, Map(jamming, ph::TargetKind::kNormalized, 0.5).target);
  LONGS_EQUAL(4370, Map(pneumatic, ph::TargetKind::kNormalized, 1).target);
  const ph::Mapped raw = Map(jamming, ph::TargetKind::kPressureKpa, -40);
  CHECK(raw.raw);
  LONGS_EQUAL(20000, raw.line_a_pa);
  LONGS_EQUAL(-40000, raw.line_b_pa);
  LONGS_EQUAL((int)pp::Status::kOutOfRange,
              (int)Map(pneumatic, ph::TargetKind::kPressureKpa, 120).status);
}

TEST(StiffnessMap, LevelFilesAreValidated) {
  const auto missing = ph::LevelTables::Load("/nonexistent.json");
  LONGS_EQUAL((int)pp::Status::kNotFound, (int)missing.status);
  CHECK(missing.message.find("/nonexistent.json: cannot be read: No such file") !=
        std::string::npos);
  const std::string path = "/tmp/palpa-levels-test-" + std::to_string(getpid()) + ".json";
  FILE* f = fopen(path.c_str(), "w");
  fputs(
      "{\"pneumatic\": {\"levels_kpa\": [0, 150]}, \"jamming\": {\"bias_kpa\": 20, \"levels_kpa\": "
      "[0]}}",
      f);
  fclose(f);
  const auto loaded = ph::LevelTables::Load(path);
  std::remove(path.c_str());
  LONGS_EQUAL((int)pp::Status::kInvalidArgument, (int)loaded.status);
  CHECK(loaded.message.find("150") != std::string::npos);
}
