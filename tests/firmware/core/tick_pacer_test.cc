// Tick pacing from the previous deadline: no drift, jitter and overruns counted.
#include "palpa/core/tick_pacer.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;

TEST_GROUP(TickPacer){};

TEST(TickPacer, PacesFromTheDeadlineNotFromTheStartTime) {
  pc::TickPacer pacer(1000);
  pacer.Start(0);
  // Every tick starts 300 us late: the deadlines stay on the 1 ms grid anyway.
  for (uint64_t k = 0; k < 100; ++k) {
    const uint64_t start = k * 1000 + 300;
    CHECK(pacer.Due(start));
    pacer.BeginTick(start);
    pacer.EndTick(start + 50);
    LONGS_EQUAL((k + 1) * 1000, pacer.deadline_us());
    CHECK_FALSE(pacer.Due(start + 650));
  }
  LONGS_EQUAL(300, pacer.stats().jitter_max_us);
  LONGS_EQUAL(0, pacer.stats().overruns);
  LONGS_EQUAL(100, pacer.stats().ticks);
  LONGS_EQUAL(50, pacer.stats().worst_tick_us);
  LONGS_EQUAL(5000, pacer.stats().busy_us);
}

TEST(TickPacer, CountsMissedPeriodsAndSkipsThem) {
  pc::TickPacer pacer(1000);
  pacer.Start(0);
  pacer.BeginTick(0);
  pacer.EndTick(3500);    // a 3.5 ms tick
  pacer.BeginTick(3500);  // serves the 1000 deadline late; 2000 and 3000 got no tick at all
  LONGS_EQUAL(2, pacer.stats().overruns);
  LONGS_EQUAL(4000, pacer.deadline_us());
  LONGS_EQUAL(3500, pacer.stats().worst_tick_us);
  LONGS_EQUAL(2500, pacer.stats().jitter_max_us);
}

TEST(TickPacer, NotDueBeforeTheDeadline) {
  pc::TickPacer pacer(1000);
  pacer.Start(5000);
  CHECK(pacer.Due(5000));
  pacer.BeginTick(5000);
  CHECK_FALSE(pacer.Due(5999));
  CHECK(pacer.Due(6000));
}
