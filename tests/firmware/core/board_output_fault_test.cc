// A digital output whose write fails (a valve driver, the supply or dump pulsing enable, the pump
// enable) latches output_write as a failed DAC write does: the detail names the output, the
// board goes safe, and the host reads both in Diagnostics.
#include "board_harness.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::BoardFrame;
using palpa::testing::BoardHarness;
namespace pp = palpa::protocol;
using pp::Fault;
using pp::FaultBit;
using pp::OutputKind;
using pp::OutputWriteDetail;

namespace {

/// What the host reads: the Diagnostics report.
pp::Diagnostics ReadDiagnostics(BoardHarness& h) {
  h.Drain();
  h.Send(pp::GetDiagnostics{});
  for (const BoardFrame& f : h.Drain()) {
    if (f.Is<pp::Diagnostics>()) return f.As<pp::Diagnostics>();
  }
  FAIL("no Diagnostics");
  return {};
}

}  // namespace

TEST_GROUP(OutputWriteFaults) {
  BoardHarness h;
  void setup() override {
    h.Connect();
    h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
    h.Send(pp::SetLineSetpoints{h.hello_nonce, 1, 1, {{{0, 30000}}}});
    h.Run(200, true);
    CHECK_FALSE(h.AllLinesSafe());
    CHECK(h.supply.changes > 100 && h.dump.changes > 100);  // both enables pulsing
    LONGS_EQUAL(0, h.board->latched_faults());
  }

  /// The fault latched with `detail`, seen by the host; every output safe and staying so while
  /// the output fails; ClearFault refused until it is written again, taken after.
  void CheckLatchedAndSafe(int32_t detail, const std::function<void()>& repair) {
    h.Run(2, true);
    const pp::Diagnostics d = ReadDiagnostics(h);
    CHECK(d.fault_bitmap & FaultBit(Fault::kOutputWrite));
    CHECK(d.history_count >= 1);
    const pp::FaultRecord& last = d.history[d.history_count - 1];
    LONGS_EQUAL(static_cast<int>(Fault::kOutputWrite), last.fault);
    LONGS_EQUAL(detail, last.detail);
    CHECK(h.board->safe());
    CHECK(h.AllLinesSafe());
    const uint32_t supply = h.supply.changes, dump = h.dump.changes;
    h.Run(20, true);
    LONGS_EQUAL(supply, h.supply.changes);  // no more pulses: the valves fall back
    LONGS_EQUAL(dump, h.dump.changes);
    CHECK_FALSE(h.supply.level || h.dump.level || h.pump.level);
    LONGS_EQUAL(1, ReadDiagnostics(h).history_count);  // latched once, not once a tick
    h.Send(pp::ClearFault{});
    LONGS_EQUAL((int)pp::Status::kConditionPersists,
                (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
    repair();
    h.Run(2, true);  // written again, and judged on the tick after
    h.Send(pp::ClearFault{});
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
  }
};

TEST(OutputWriteFaults, TheSupplyEnableNamedAsASharedOutput) {
  h.supply.fail = true;  // the enable keeps its last level: the board must not count on it
  CheckLatchedAndSafe(OutputWriteDetail(OutputKind::kSupplyEnable), [&] { h.supply.fail = false; });
}

TEST(OutputWriteFaults, TheDumpEnable) {
  h.dump.fail = true;
  CheckLatchedAndSafe(OutputWriteDetail(OutputKind::kDumpEnable), [&] { h.dump.fail = false; });
}

TEST(OutputWriteFaults, ThePumpEnable) {
  h.pump.fail = true;
  CheckLatchedAndSafe(OutputWriteDetail(OutputKind::kPumpEnable), [&] { h.pump.fail = false; });
}

TEST(OutputWriteFaults, ALineValveNamedByItsLineAndRetriedEveryTick) {
  // Line 0 shaped (its chamber's lag known, an overdrive): at atmosphere it opens its own dump
  // valve, and that write fails.
  pp::ConfigureLine shaped = h.board->config().lines[0];
  shaped.slew_pa_per_s = 0;
  shaped.chamber_tau_us = 6000;
  shaped.overdrive_pa = 20000;
  h.Send(shaped);
  h.Send(pp::SetLineSetpoints{h.hello_nonce, 2, 1, {{{0, 30000}}}});
  h.Run(200, true);
  CHECK_FALSE(h.board->safe());
  LONGS_EQUAL(0, h.board->line_vents() & 1u);
  h.vents.fail_bit = 0;
  h.Send(pp::SetLineSetpoints{h.hello_nonce, 3, 1, {{{0, 0}}}});
  h.Run(50, true);
  const uint32_t writes = h.vents.writes;
  CheckLatchedAndSafe(OutputWriteDetail(OutputKind::kLineValve, 0), [&] {
    CHECK(h.vents.writes > writes + 20);  // every tick while it fails
    h.vents.fail_bit = palpa::hal::DigitalPort::kAllWritten;
  });
  LONGS_EQUAL(h.board->line_vents(), h.vents.bits);  // written once it could be
}
