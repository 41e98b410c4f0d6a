// Configuration store: two copies with CRC, newest valid wins, torn writes fall back.
#include <cstring>

#include "palpa/core/board_configs.h"
#include "palpa/core/config_store.h"
#include "palpa/hal/fake/simulated_nor_flash.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;

TEST_GROUP(ConfigStore) {
  palpa::hal::fake::SimulatedNorFlash flash{64 * 1024, 8 * 1024, 3};
  const pc::BoardConfig& factory = *pc::FindBoardConfig("thesis-5finger");
  pc::BoardConfig Modified(uint32_t slew) {
    pc::BoardConfig c = factory;
    c.lines[0].slew_pa_per_s = slew;
    return c;
  }
};

TEST(ConfigStore, EmptyFlashGivesTheFactoryDefaults) {
  pc::ConfigStore store(&flash, 0);
  pc::BoardConfig c{};
  CHECK(store.Load(factory, c) == pc::ConfigStore::Source::kFactory);
  LONGS_EQUAL(pc::ConfigCrc(factory), pc::ConfigCrc(c));
}

TEST(ConfigStore, SavedConfigurationComesBack) {
  pc::ConfigStore store(&flash, 0);
  LONGS_EQUAL((int)pp::Status::kOk, (int)store.Save(Modified(90000)));
  LONGS_EQUAL((int)pp::Status::kOk, (int)store.Save(Modified(80000)));
  pc::ConfigStore reboot(&flash, 0);
  pc::BoardConfig c{};
  CHECK(reboot.Load(factory, c) == pc::ConfigStore::Source::kFlash);
  LONGS_EQUAL(80000, c.lines[0].slew_pa_per_s);
  LONGS_EQUAL(2, reboot.sequence());
}

TEST(ConfigStore, TornSaveBootsFromTheOtherCopyAtEveryCutPoint) {
  for (uint32_t cut = 0; cut < 8192 + 1200; cut += 97) {
    palpa::hal::fake::SimulatedNorFlash f{64 * 1024, 8 * 1024, cut};
    pc::ConfigStore store(&f, 0);
    store.Save(Modified(90000));
    f.CutPowerAfter(cut);
    const pp::Status s = store.Save(Modified(70000));
    f.PowerOn();
    pc::ConfigStore reboot(&f, 0);
    pc::BoardConfig c{};
    CHECK(reboot.Load(factory, c) == pc::ConfigStore::Source::kFlash);
    if (s == pp::Status::kOk) {
      LONGS_EQUAL(70000, c.lines[0].slew_pa_per_s);
    } else {
      LONGS_EQUAL(90000, c.lines[0].slew_pa_per_s);  // the interrupted copy is never used
    }
  }
}

TEST(ConfigStore, CorruptedCopyIsSkipped) {
  pc::ConfigStore store(&flash, 0);
  store.Save(Modified(90000));
  store.Save(Modified(80000));  // second copy, in sector 1
  const uint8_t zero = 0;
  flash.Program(8 * 1024 + 100, &zero, 1);  // clear bits in the newest copy's blob
  pc::BoardConfig c{};
  pc::ConfigStore reboot(&flash, 0);
  CHECK(reboot.Load(factory, c) == pc::ConfigStore::Source::kFlash);
  LONGS_EQUAL(90000, c.lines[0].slew_pa_per_s);
}

TEST(ConfigStore, AnInvalidSavedConfigurationIsNotLoaded) {
  pc::BoardConfig c = factory;
  c.lines[0].limit_max_pa = 90000;  // finger 0's inverse reaches 100 kPa: invalid as a whole
  pc::ConfigStore store(&flash, 0);
  LONGS_EQUAL((int)pp::Status::kOk, (int)store.Save(c));
  pc::BoardConfig loaded{};
  CHECK(store.Load(factory, loaded) == pc::ConfigStore::Source::kFactory);
}

TEST(ConfigStore, EraseReturnsToFactoryAndNoFlashMeansFactory) {
  pc::ConfigStore store(&flash, 0);
  store.Save(Modified(90000));
  LONGS_EQUAL((int)pp::Status::kOk, (int)store.Erase());
  pc::BoardConfig c{};
  CHECK(store.Load(factory, c) == pc::ConfigStore::Source::kFactory);
  pc::ConfigStore none(nullptr, 0);
  CHECK(none.Load(factory, c) == pc::ConfigStore::Source::kFactory);
  LONGS_EQUAL((int)pp::Status::kUnavailable, (int)none.Save(factory));
}
