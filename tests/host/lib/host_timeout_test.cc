// The host-silence timeout the host follows through a session, and the heartbeat period from it.
#include "palpa/host/host_timeout.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;

TEST_GROUP(HeartbeatPeriod){};

TEST(HeartbeatPeriod, AQuarterOfTheTimeoutInHostTime) {
  DOUBLES_EQUAL(0.025, ph::HeartbeatPeriodSeconds(100000, 1.0f), 1e-12);
  DOUBLES_EQUAL(0.005, ph::HeartbeatPeriodSeconds(20000, 1.0f), 1e-12);
  DOUBLES_EQUAL(0.05, ph::HeartbeatPeriodSeconds(20000, 0.1f),
                1e-9);  // a board at a tenth of real time
  DOUBLES_EQUAL(0.0025, ph::HeartbeatPeriodSeconds(100000, 10.0f), 1e-12);
}

TEST(HeartbeatPeriod, NoTimeoutReportedMeansTheDefaultAndNoScaleMeansRealTime) {
  DOUBLES_EQUAL(0.025, ph::HeartbeatPeriodSeconds(0, 1.0f), 1e-12);
  DOUBLES_EQUAL(0.025, ph::HeartbeatPeriodSeconds(100000, 0.0f), 1e-12);
  DOUBLES_EQUAL(0.025, ph::HeartbeatPeriodSeconds(100000, -2.0f), 1e-12);
}

TEST(HeartbeatPeriod, NeverBelowOneMillisecond) {
  DOUBLES_EQUAL(0.001, ph::HeartbeatPeriodSeconds(10000, 100.0f), 1e-12);
}

TEST_GROUP(HostTimeoutTracker) {
  ph::HostTimeoutTracker tracker;
  void setup() override { tracker.OnSession(100000, 1.0f); }
};

TEST(HostTimeoutTracker, ASessionStartsFromTheBoardsValueOrTheDefault) {
  LONGS_EQUAL(100000, tracker.EffectiveTimeoutUs());
  tracker.OnSession(0, 1.0f);
  LONGS_EQUAL(ph::kDefaultHostTimeoutUs, tracker.EffectiveTimeoutUs());
  tracker.OnSession(40000, 0.5f);
  LONGS_EQUAL(40000, tracker.EffectiveTimeoutUs());
  DOUBLES_EQUAL(0.02, tracker.HeartbeatPeriodSeconds(), 1e-12);
}

TEST(HostTimeoutTracker, AShorterTimeoutCountsFromTheMomentItIsSent) {
  tracker.OnSent(7, 20000);
  LONGS_EQUAL(20000, tracker.EffectiveTimeoutUs());  // before the board can apply it
  tracker.OnApplied(7);
  LONGS_EQUAL(20000, tracker.EffectiveTimeoutUs());
}

TEST(HostTimeoutTracker, ALongerTimeoutCountsOnlyOnceApplied) {
  tracker.OnSent(7, 500000);
  LONGS_EQUAL(100000, tracker.EffectiveTimeoutUs());
  tracker.OnApplied(7);
  LONGS_EQUAL(500000, tracker.EffectiveTimeoutUs());
}

TEST(HostTimeoutTracker, ARefusedChangeLeavesTheOldValue) {
  tracker.OnSent(7, 20000);
  tracker.OnRefused(7);
  LONGS_EQUAL(100000, tracker.EffectiveTimeoutUs());
}

TEST(HostTimeoutTracker, AnUnknownOutcomeKeepsTheShorterOfBoth) {
  tracker.OnSent(7, 30000);
  tracker.OnUnknown(7);
  LONGS_EQUAL(30000, tracker.EffectiveTimeoutUs());
  tracker.OnSent(8, 200000);
  tracker.OnUnknown(8);
  LONGS_EQUAL(30000, tracker.EffectiveTimeoutUs());
}

TEST(HostTimeoutTracker, ANewSessionForgetsWhatWasInFlight) {
  tracker.OnSent(7, 15000);
  tracker.OnSession(100000, 1.0f);
  LONGS_EQUAL(100000, tracker.EffectiveTimeoutUs());
  tracker.OnApplied(7);  // an answer from the old session changes nothing
  LONGS_EQUAL(100000, tracker.EffectiveTimeoutUs());
}

TEST(HostTimeoutTracker, EveryChangeIsCountedSoAWaitingLoopWakes) {
  const uint64_t before = tracker.changes();
  tracker.OnSent(7, 20000);
  tracker.OnApplied(7);
  tracker.Set(50000);
  LONGS_EQUAL(before + 3, tracker.changes());
  LONGS_EQUAL(50000, tracker.EffectiveTimeoutUs());
  tracker.OnRefused(99);  // unknown: nothing changed
  LONGS_EQUAL(before + 3, tracker.changes());
}
