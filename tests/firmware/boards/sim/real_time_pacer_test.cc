// palpa-sim's real-time pacing: the virtual clock it targets, its slips, its batched wakes, its
// hold to real time near the host-silence deadline and the host's silence judged in real time.
#include "real_time_pacer.h"

#include "CppUTest/TestHarness.h"

using palpa::sim::HostNearSilenceTimeout;
using palpa::sim::RealTimePacer;

TEST_GROUP(RealTimePacer){};

TEST(RealTimePacer, WakesForEveryStepUpToRealTimeAndBatchesAbove) {
  CHECK_EQUAL(1u, RealTimePacer(0.01).steps_per_wake());
  CHECK_EQUAL(1u, RealTimePacer(1).steps_per_wake());
  CHECK_EQUAL(2u, RealTimePacer(2.5).steps_per_wake());
  CHECK_EQUAL(10u, RealTimePacer(10).steps_per_wake());
  // Capped in virtual time: the board still reads the host every 10 board milliseconds.
  CHECK_EQUAL(10u, RealTimePacer(100).steps_per_wake());
}

TEST(RealTimePacer, TargetsScaledRealTime) {
  RealTimePacer pacer(10);
  CHECK_EQUAL(0u, pacer.Target(0, 0));
  CHECK_EQUAL(15000u, pacer.Target(1500, 0));  // 1.5 ms real at 10x, within the lag allowed
}

TEST(RealTimePacer, SlipsInsteadOfRacingWhenFarBehind) {
  RealTimePacer pacer(1);
  // 50 ms behind: one step further, and the other 49 ms of real time are given up.
  CHECK_EQUAL(6000u, pacer.Target(55000, 5000));
  // Afterwards virtual time follows real time from where it slipped to.
  CHECK_EQUAL(7000u, pacer.Target(56000, 6000));
  CHECK_EQUAL(6000u + RealTimePacer::kMaxLagUs,
              pacer.Target(55000 + static_cast<double>(RealTimePacer::kMaxLagUs), 6000));
  DOUBLES_EQUAL(1000, pacer.WaitUs(55000, 6000), 1e-9);  // board 7 ms is due at 56 ms real
}

TEST(RealTimePacer, SleepsUntilABatchIsDue) {
  RealTimePacer real_time(1);
  DOUBLES_EQUAL(600, real_time.WaitUs(3400, 3000), 1e-9);  // the next step, at 4 ms
  DOUBLES_EQUAL(0, real_time.WaitUs(4100, 3000), 0);       // already due: no sleep
  RealTimePacer fast(10);
  // Ten steps after board time 3 ms, i.e. board 13 ms = 1.3 ms real.
  DOUBLES_EQUAL(900, fast.WaitUs(400, 3000), 1e-9);
  RealTimePacer slow(0.5);
  DOUBLES_EQUAL(2000, slow.WaitUs(6000, 3000), 1e-9);  // board 4 ms = 8 ms real
}

TEST(RealTimePacer, HeldToRealTimeContinuesFromTheBoardsTimeAndReleasesToItsSpeed) {
  RealTimePacer pacer(10);
  CHECK_EQUAL(50000u, pacer.Target(5000, 50000));
  pacer.HoldToRealTime(true, 5000, 50000);
  DOUBLES_EQUAL(1, pacer.pace(), 0);
  CHECK_EQUAL(1u, pacer.steps_per_wake());
  CHECK_EQUAL(50000u, pacer.Target(5000, 50000));   // no jump at the change
  CHECK_EQUAL(57000u, pacer.Target(12000, 50000));  // 7 ms real: 7 board ms, not 70
  DOUBLES_EQUAL(1000, pacer.WaitUs(12000, 57000), 1e-9);
  pacer.HoldToRealTime(true, 12000, 57000);  // holding again changes nothing
  CHECK_EQUAL(58000u, pacer.Target(13000, 57000));
  pacer.HoldToRealTime(false, 13000, 58000);
  DOUBLES_EQUAL(10, pacer.pace(), 0);
  CHECK_EQUAL(68000u, pacer.Target(14000, 58000));  // 10x again from there
}

TEST(RealTimePacer, ASlowerSpeedIsNotSpedUpByTheHold) {
  RealTimePacer pacer(0.5);
  pacer.HoldToRealTime(true, 1000, 0);
  DOUBLES_EQUAL(0.5, pacer.pace(), 0);
  CHECK_EQUAL(1000u, pacer.Target(2000, 0));
}

TEST(RealTimePacer, HoldsOnlyBetweenHalfTheHostTimeoutAndTheTimeout) {
  const uint32_t timeout = 100000;
  CHECK_FALSE(HostNearSilenceTimeout(true, 150000, 100000, timeout));  // 50 ms: not yet
  CHECK(HostNearSilenceTimeout(true, 151000, 100000, timeout));
  CHECK(HostNearSilenceTimeout(true, 200000, 100000, timeout));
  CHECK_FALSE(HostNearSilenceTimeout(true, 201000, 100000, timeout));   // past it: board safe
  CHECK_FALSE(HostNearSilenceTimeout(false, 170000, 100000, timeout));  // no session
  CHECK_FALSE(HostNearSilenceTimeout(true, 90000, 100000, timeout));    // frame stamped ahead
}

TEST(RealTimePacer, TheHostsSilenceIsJudgedInRealTimeToo) {
  using palpa::sim::HostSilenceLimitUs;
  const uint32_t timeout = 100000;
  // Last frame at board 1 s, 25 ms of real time ago (100 board ms at 4x): the board may reach
  // the deadline but not pass it, so a descheduled host is not yet silent for the board.
  CHECK_EQUAL(1100000u, HostSilenceLimitUs(true, 1000000, timeout, 25000));
  CHECK_EQUAL(1100000u, HostSilenceLimitUs(true, 1000000, timeout, 99999));
  // Silent for the timeout in real time as well: nothing holds the board, which faults.
  CHECK_EQUAL(UINT64_MAX, HostSilenceLimitUs(true, 1000000, timeout, 100000));
  CHECK_EQUAL(UINT64_MAX, HostSilenceLimitUs(false, 1000000, timeout, 0));  // no session
}

TEST(RealTimePacer, RunningTimeLeavesOutWhatTheWakesCameLate) {
  RealTimePacer pacer(10);
  DOUBLES_EQUAL(5000, pacer.RunningUs(5000), 0);
  pacer.Woke(5000, 1000, 5400);  // woken early, by a frame
  pacer.Woke(5400, 1000, 8300);  // later than asked, but within what a wake and a batch take
  DOUBLES_EQUAL(8300, pacer.RunningUs(8300), 0);
  // 200 ms without the processor: the board could not look, the host could not be heard.
  pacer.Woke(8300, 1000, 208300);
  const double running = 8300 + 1000 + RealTimePacer::kLateUs;
  DOUBLES_EQUAL(running, pacer.RunningUs(208300), 1e-9);
  DOUBLES_EQUAL(running + 50000, pacer.RunningUs(258300), 1e-9);  // and on from there
}
