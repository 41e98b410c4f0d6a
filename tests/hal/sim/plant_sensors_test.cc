// The plant's sensors: ideal below level 3, within their accuracy and resolution at it, seeded.
#include <cmath>

#include "palpa/hal/sim/plant.h"
#include "plant_test_support.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
using palpa::sim::testing::Hold;
using palpa::sim::testing::MakePlant;

TEST_GROUP(PlantSensors){};

TEST(PlantSensors, IdealBelowLevelThreeAndWithinAccuracyAtIt) {
  ps::PressureSensor ideal(0, 103421, true, 1);
  DOUBLES_EQUAL(50000, ideal.PressureOf(ideal.Read(50000, 0.001f)), 8);
  for (uint32_t seed = 1; seed < 40; ++seed) {
    ps::PressureSensor real(0, 103421, false, seed);
    double sum = 0;
    for (int i = 0; i < 200; ++i) sum += real.PressureOf(real.Read(50000, 0.001f));
    DOUBLES_EQUAL(50000, sum / 200, 0.0025 * 103421 + 20);
  }
}

TEST(PlantSensors, ForceSensorResolution) {
  ps::ForceSensor f(true, 1);
  DOUBLES_EQUAL(1.002, f.Read(1.0031), 1e-6);
  ps::LinearStage stage;
  stage.MoveTo(3.0f, 0.1f);
  for (int i = 0; i < 10000; ++i) stage.Step(0.001f);
  DOUBLES_EQUAL(1.0, stage.position_mm(), 1e-4);
}

TEST(PlantSensors, SameSeedSameRun) {
  auto run = [](uint32_t seed) {
    ps::Plant plant = MakePlant(3, 2, seed);
    Hold(plant, 0, 30000, 500);
    return plant.SensorCounts(0) * 100000u + plant.SensorCounts(5);
  };
  LONGS_EQUAL(run(4), run(4));
  CHECK(run(4) != run(5));
}
