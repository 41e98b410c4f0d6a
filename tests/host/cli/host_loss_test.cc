// Killing the host mid-stream leaves the board safe: 100 randomised trials against palpa-sim.
#include <string>

#include "host_loss.h"

#include "CppUTest/TestHarness.h"

TEST_GROUP(HostLoss){};

TEST(HostLoss, KilledHostLeavesTheBoardSafeInHundredRandomTrials) {
  const palpa::testing::HostLossResult r = palpa::testing::RunHostLossTrials(100, 2026, 2.0);
  CHECK_TEXT(r.error.empty(), r.error.c_str());
  LONGS_EQUAL(100, r.trials);
  LONGS_EQUAL(100, r.safe_in_time);
  LONGS_EQUAL(100, r.vented_in_time);
  LONGS_EQUAL(100, r.host_silence);  // a kill is not a Close: the fault is latched
}
