// Supervisor: every fault path latches, ClearFault is refused while the cause persists; fast
// checks see every line every tick, slow monitors every line within kMaxLines ticks.
#include "palpa/core/supervisor.h"

#include "CppUTest/TestHarness.h"

namespace pc = palpa::core;
namespace pp = palpa::protocol;
using pp::Fault;
using pp::FaultBit;

namespace {

constexpr uint64_t kTick = 1000;  // µs: the board calls the supervisor every tick

struct Fixture {
  pc::SupervisorSettings settings;
  pc::SupervisorState state;
  pc::SupervisorInput in;
  Fixture() {
    settings.host_timeout_us = 100000;
    settings.sensor_window_us = 3000000;
    settings.leak_timeout_us = 5000000;
    settings.pump_max_run_us = 60000000;
    settings.tolerance_pa = 5000;
    in.session_open = true;
    pc::LineObservation& o = in.lines[0];
    o.configured = o.has_sensor = o.reading.valid = o.closed_loop = true;
    o.alarm_below_pa = 0 - settings.tolerance_pa;  // limits 0..100 kPa
    o.alarm_above_pa = 100000 + settings.tolerance_pa;
  }
  /// A tick at `now_us`: the readings summarised as the board's sensing stage does, then judged.
  uint32_t At(uint64_t now_us) {
    in.now_us = now_us;
    in.readings = {};
    for (uint8_t i = 0; i < pp::kMaxLines; ++i) {
      if (in.lines[i].configured && in.lines[i].has_sensor)
        pc::NoteReading(in.readings, i, in.lines[i].reading, in.lines[i]);
    }
    return pc::Supervise(settings, state, in);
  }
  /// One tick of a live session: the host's heartbeat has just arrived.
  uint32_t Tick(uint64_t now_us) {
    in.last_host_frame_us = now_us;
    return At(now_us);
  }
  void Line(float setpoint, float reference, float measured, uint32_t counts) {
    pc::LineObservation& o = in.lines[0];
    o.setpoint_pa = setpoint;
    o.reference_pa = reference;
    o.reading.pa = measured;
    o.raw_counts = counts;
  }
};

}  // namespace

TEST_GROUP(Supervisor){};

TEST(Supervisor, HostSilenceLatchesAfterTheTimeoutAndClearsOnlyWhenTheHostIsBack) {
  Fixture f;
  f.in.actuating = true;
  f.in.last_host_frame_us = 1000000;
  LONGS_EQUAL(0, f.At(1100000));
  CHECK_FALSE(pc::HostSilent(f.settings, f.in));
  LONGS_EQUAL(FaultBit(Fault::kHostSilence), f.At(1100001));
  LONGS_EQUAL((int)pp::Status::kConditionPersists, (int)pc::ClearFaults(f.state, pp::kAllFaults));
  f.in.last_host_frame_us = 1200000;
  f.At(1200001);
  LONGS_EQUAL((int)pp::Status::kOk, (int)pc::ClearFaults(f.state, pp::kAllFaults));
  LONGS_EQUAL(0, f.state.latched);
}

TEST(Supervisor, NoHostSilenceWithoutASession) {
  Fixture f;
  f.in.actuating = true;
  f.in.session_open = false;
  LONGS_EQUAL(0, f.At(100000000));
  CHECK_FALSE(pc::HostSilent(f.settings, f.in));
}

TEST(Supervisor, ASilentHostThatLeftTheBoardSafeIsNoFault) {
  // The session ends (HostSilent, which the board acts on) but nothing latches: the host left
  // nothing actuated.
  Fixture f;
  f.in.actuating = false;
  f.in.last_host_frame_us = 1000000;
  LONGS_EQUAL(0, f.At(1100001));
  CHECK(pc::HostSilent(f.settings, f.in));
  CHECK(f.state.host_silent);  // what the board ends the session on
  LONGS_EQUAL(0, f.state.latched);
  LONGS_EQUAL(0, f.state.active);
}

TEST(Supervisor, OverLimitReadingLatchesAtOnce) {
  Fixture f;
  f.in.last_host_frame_us = 0;
  f.Line(50000, 50000, 105001, 100);
  LONGS_EQUAL(FaultBit(Fault::kOverLimit), f.At(1000));
}

TEST(Supervisor, ReadingOutsideTheSensorSpanIsImplausibleAtOnce) {
  Fixture f;
  f.in.lines[0].reading.valid = false;
  LONGS_EQUAL(FaultBit(Fault::kImplausibleSensor), f.At(1000));
}

TEST(Supervisor, OverLimitAndInvalidReadingsAreSeenOnEveryLineAtTheFirstTick) {
  Fixture f;
  for (uint8_t i = 1; i < pp::kMaxLines; ++i) f.in.lines[i] = f.in.lines[0];
  f.in.lines[6].reading.pa = 105001;
  LONGS_EQUAL(FaultBit(Fault::kOverLimit), f.At(1000));
  f.in.lines[3].reading.valid = false;
  LONGS_EQUAL(FaultBit(Fault::kImplausibleSensor), f.At(2000));
  pp::FaultRecord records[pp::kMaxFaultRecords];
  LONGS_EQUAL(2, pc::FaultHistory(f.state, records));
  LONGS_EQUAL(105001, records[0].detail);
  LONGS_EQUAL(3, records[1].detail);
}

TEST(Supervisor, SensorAboveTheModelLongerThanTheWindowIsImplausible) {
  Fixture f;
  f.Line(20000, 20000, 40000, 100);
  uint64_t t = 1000;
  for (; t <= 3001000; t += kTick) {  // the window, from the first visit of the line
    f.Tick(t);
    f.in.lines[0].raw_counts = static_cast<uint32_t>(t);  // noise: not stuck
    LONGS_EQUAL(0, f.state.latched);
  }
  // The slow monitors visit each line slot every kMaxLines ticks: tripped by the next visit.
  while (f.state.latched == 0 && t <= 3001000 + pp::kMaxLines * kTick) f.Tick(t += kTick);
  LONGS_EQUAL(FaultBit(Fault::kImplausibleSensor), f.state.latched);
}

TEST(Supervisor, ShortTransientsAreNotImplausible) {
  Fixture f;
  for (uint64_t t = 0; t < 20000000; t += kTick) {
    const bool transient = (t / 1000000) % 2 == 0;  // 1 s over, 1 s fine
    f.Line(20000, 20000, transient ? 40000 : 20000, static_cast<uint32_t>(t));
    LONGS_EQUAL(0, f.Tick(t));
  }
}

TEST(Supervisor, StuckSensorWhileTheCommandMovesIsImplausible) {
  Fixture f;
  for (uint64_t t = 0; t <= 3200000; t += kTick) {
    const float reference = static_cast<float>(t) / 100.0f;  // ramps 0 → 32 kPa
    f.Line(reference, reference, 0, 777);  // same counts all along, reading stays at 0
    f.Tick(t);
  }
  CHECK(f.state.latched & FaultBit(Fault::kImplausibleSensor));
}

TEST(Supervisor, LeakWhenTheChamberNeverReachesASettledSetpoint) {
  Fixture f;
  uint32_t newly = 0;
  for (uint64_t t = 0; t <= 5200000; t += kTick) {
    f.Line(50000, 50000, 30000, static_cast<uint32_t>(t));
    newly |= f.Tick(t);
  }
  LONGS_EQUAL(FaultBit(Fault::kLeak), newly);
}

TEST(Supervisor, TheSlowMonitorsVisitEveryLineInTurn) {
  Fixture f;
  f.in.lines[7] = f.in.lines[0];
  f.in.lines[0].configured = false;
  pc::LineObservation& o = f.in.lines[7];  // short of its settled setpoint: a leak
  o.setpoint_pa = o.reference_pa = 50000;
  o.reading.pa = 30000;
  uint64_t t = 0;
  uint32_t newly = 0;
  for (; newly == 0 && t <= 6000000; t += kTick) {
    o.raw_counts = static_cast<uint32_t>(t);
    newly = f.Tick(t);
  }
  LONGS_EQUAL(FaultBit(Fault::kLeak), newly);
  // First visit at tick 7 (7 ms), tripped at the first visit past the 5 s timeout.
  CHECK(t - kTick > 5007000);
  CHECK(t - kTick <= 5007000 + pp::kMaxLines * kTick);
  pp::FaultRecord records[pp::kMaxFaultRecords];
  LONGS_EQUAL(1, pc::FaultHistory(f.state, records));
  LONGS_EQUAL(7, records[0].detail);
}

TEST(Supervisor, EStopPinLatchesAndBlocksClearingWhileAsserted) {
  Fixture f;
  f.in.estop_pin = true;
  LONGS_EQUAL(FaultBit(Fault::kEStopPin), f.At(1));
  f.in.last_host_frame_us = 2;
  f.At(2);
  LONGS_EQUAL((int)pp::Status::kConditionPersists,
              (int)pc::ClearFaults(f.state, FaultBit(Fault::kEStopPin)));
  f.in.estop_pin = false;
  f.At(3);
  LONGS_EQUAL((int)pp::Status::kOk, (int)pc::ClearFaults(f.state, FaultBit(Fault::kEStopPin)));
}

TEST(Supervisor, AFailedOutputWriteLatchesAndPersistsWhileWritesFail) {
  Fixture f;
  f.in.failed_output = 3;
  LONGS_EQUAL(FaultBit(Fault::kOutputWrite), f.Tick(1000));
  LONGS_EQUAL((int)pp::Status::kConditionPersists, (int)pc::ClearFaults(f.state, pp::kAllFaults));
  f.in.failed_output = pc::kNoFailedOutput;
  f.Tick(2000);
  LONGS_EQUAL((int)pp::Status::kOk, (int)pc::ClearFaults(f.state, pp::kAllFaults));
  pp::FaultRecord records[pp::kMaxFaultRecords];
  LONGS_EQUAL(1, pc::FaultHistory(f.state, records));
  LONGS_EQUAL(3, records[0].detail);
}

TEST(Supervisor, ConfigCrcFailureLatches) {
  Fixture f;
  f.in.config_intact = false;
  LONGS_EQUAL(FaultBit(Fault::kConfigCrc), f.At(1));
}

TEST(Supervisor, PumpRunsOnlyOnDemandAndNeverLongerThanAllowed) {
  Fixture f;
  f.in.vacuum_demand = true;
  f.At(1);
  CHECK(f.state.pump_on);
  for (uint64_t t = 1; t < 60000000; t += 1000000) {
    f.in.last_host_frame_us = t;
    f.in.lines[0].raw_counts = static_cast<uint32_t>(t);
    f.Line(0, 0, 0, static_cast<uint32_t>(t));
    f.At(t);
  }
  f.in.last_host_frame_us = 60000002;
  CHECK(f.At(60000002) & FaultBit(Fault::kPumpRunTime));
  CHECK_FALSE(f.state.pump_on);
}

TEST(Supervisor, HistoryKeepsTheLatestSixteenOldestFirst) {
  pc::SupervisorState s;
  for (int i = 0; i < 20; ++i) {
    pc::LatchFault(s, static_cast<Fault>(i % 9), static_cast<uint64_t>(i), i);
    s.latched = 0;  // let the same fault latch again
  }
  pp::FaultRecord records[pp::kMaxFaultRecords];
  LONGS_EQUAL(16, pc::FaultHistory(s, records));
  LONGS_EQUAL(4, records[0].time_us);
  LONGS_EQUAL(19, records[15].time_us);
}
