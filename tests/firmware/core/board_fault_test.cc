// Faults through the whole board: host silence timing, E-stop, refusal rules while faulted,
// clearing, configuration CRC, unexpected reset, persistence.
#include <algorithm>
#include <random>
#include <string>
#include <utility>

#include "board_harness.h"
#include "palpa/protocol/crc32.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::BoardFrame;
using palpa::testing::BoardHarness;
namespace pp = palpa::protocol;
namespace pc = palpa::core;
using pp::Fault;
using pp::FaultBit;

namespace {

void RawSetpoints(BoardHarness& h, uint32_t generation, int32_t pa) {
  pp::SetLineSetpoints m{};
  m.generation = generation;
  m.entry_count = 1;
  m.entries[0] = {0, pa};
  h.Send(m);
}

}  // namespace

TEST_GROUP(HostSilence){};

TEST(HostSilence, SafeCommandWrittenWithinTimeoutPlusOneTickInRandomTrials) {
  std::mt19937 rng(12345);
  BoardHarness h;
  uint32_t generation = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    h.Connect(static_cast<uint8_t>(rng()));
    h.Send(pp::ClearFault{});
    h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
    RawSetpoints(h, ++generation, 5000 + static_cast<int32_t>(rng() % 90000));
    // Run a random while with heartbeats, then the host goes quiet at a random instant.
    const uint32_t busy_ms = 20 + rng() % 200;
    for (uint32_t ms = 0; ms < busy_ms; ++ms) {
      h.Run(1, ms % 20 == 0);
      h.FollowModel();
    }
    CHECK_FALSE(h.board->safe());
    h.clock.Advance(rng() % pc::Board::kTickUs);  // last frame anywhere inside a tick
    h.Send(pp::Heartbeat{h.hello_nonce, ++h.generation}, false);
    const uint64_t last_frame = h.clock.now_us;
    uint64_t safe_at = 0;
    while (safe_at == 0 && h.clock.now_us < last_frame + 1000000) {
      h.clock.Advance(pc::Board::kTickUs - h.clock.now_us % pc::Board::kTickUs);  // next tick edge
      h.board->Step();
      if (h.AllLinesSafe()) safe_at = h.clock.now_us;
    }
    CHECK(safe_at != 0);
    CHECK_TEXT(safe_at - last_frame <= 100000 + pc::Board::kTickUs,
               std::to_string(safe_at - last_frame).c_str());
    CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
    h.Drain();
  }
}

TEST_GROUP(BoardFaults) {
  BoardHarness h;
  void setup() override {
    h.Connect();
    h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
    RawSetpoints(h, 1, 30000);
    h.Run(200, true);
    h.Drain();
  }
};

TEST(BoardFaults, EStopGoesSafeOnTheNextTickAndIsAcked) {
  CHECK_FALSE(h.AllLinesSafe());
  h.Send(pp::EStop{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kEStop));
  h.Run(1, true);
  CHECK(h.AllLinesSafe());
  CHECK(h.board->latched_faults() & FaultBit(Fault::kEStopCommand));
}

TEST(BoardFaults, WhileFaultedSetpointsAreNackedAndTheRestWorks) {
  h.Send(pp::EStop{});
  h.Run(1, true);
  h.Drain();
  RawSetpoints(h, 2, 10000);
  h.Send(pp::GetConfig{pp::ConfigSection::kLine, 2, 0});
  h.Send(pp::GetDiagnostics{});
  pp::ConfigureBoard board = h.board->config().board;
  board.host_timeout_us = 200000;
  h.Send(board);
  h.Send(pp::SaveConfig{});
  const auto frames = h.Drain();
  LONGS_EQUAL((int)pp::Status::kFaulted,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kSetLineSetpoints));
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kConfigureBoard));
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kSaveConfig));
  bool report = false, diagnostics = false;
  for (const BoardFrame& f : frames) {
    if (f.Is<pp::ConfigReport>()) {
      report = true;
      pp::ConfigureLine line{};
      const auto r = f.As<pp::ConfigReport>();
      LONGS_EQUAL(r.total_bytes, r.data_size);
      LONGS_EQUAL((int)pp::Status::kOk, (int)pp::DecodeBody(r.data.data(), r.data_size, line));
      LONGS_EQUAL(2, line.line);
    }
    if (f.Is<pp::Diagnostics>()) {
      diagnostics = true;
      const auto d = f.As<pp::Diagnostics>();
      CHECK(d.fault_bitmap & FaultBit(Fault::kEStopCommand));
      LONGS_EQUAL(1, d.history_count);
    }
  }
  CHECK(report && diagnostics);
  LONGS_EQUAL(200000, h.board->config().board.host_timeout_us);
}

TEST(BoardFaults, ClearedFaultKeepsOutputsSafeUntilNewSetpointsAndRehomes) {
  h.Send(pp::EStop{});
  h.Run(5, true);
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
  LONGS_EQUAL(0, h.board->latched_faults());
  h.Run(50, true);
  CHECK(h.AllLinesSafe());  // the old setpoint does not come back by itself
  RawSetpoints(h, 9, 10000);
  h.Run(100, true);
  CHECK_FALSE(h.AllLinesSafe());
}

TEST(BoardFaults, ClearFaultIsRefusedWhileTheEStopPinIsHeld) {
  h.estop.level = true;
  h.Run(2, true);
  CHECK(h.AllLinesSafe());
  h.Drain();
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kConditionPersists,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
  h.estop.level = false;
  h.Run(2, true);
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
}

TEST(BoardFaults, FlippedByteInTheLiveConfigurationFaultsWithinTheCheckPeriod) {
  const uint32_t period_us = h.board->config().board.config_check_period_ms * 1000u;
  reinterpret_cast<uint8_t*>(&h.board->live_config_for_test())[1234] ^= 0x10;
  const uint64_t flipped_at = h.clock.now_us;
  while ((h.board->latched_faults() & FaultBit(Fault::kConfigCrc)) == 0 &&
         h.clock.now_us < flipped_at + 10 * period_us) {
    h.Run(1, true);
  }
  CHECK(h.board->latched_faults() & FaultBit(Fault::kConfigCrc));
  // One full pass of the CRC over the configuration takes a few ticks after each period starts.
  CHECK(h.clock.now_us - flipped_at <= period_us + 20 * pc::Board::kTickUs);
  CHECK(h.AllLinesSafe());
}

TEST(BoardFaults, SensorReadingBeyondTheLimitsFaults) {
  h.SetMeasured(0, 102000);  // 100 kPa line limit + 5 kPa tolerance → 105 kPa: not yet
  h.Run(2, true);
  LONGS_EQUAL(0, h.board->latched_faults() & FaultBit(Fault::kOverLimit));
  h.adc.counts[0] = 14745;  // sensor's 103.4 kPa
  h.SetMeasured(0, 106000);
  h.Run(2, true);
  CHECK(h.board->latched_faults() &
        (FaultBit(Fault::kOverLimit) | FaultBit(Fault::kImplausibleSensor)));
  CHECK(h.AllLinesSafe());
}

TEST(BoardFaults, BrokenSensorWireIsImplausible) {
  h.adc.counts[2] = 0;  // below the 10 % output floor: an open wire
  h.Run(2, true);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kImplausibleSensor));
}

TEST(BoardFaults, ReadingsWithinTwoPercentOfTheSensorSpanAreStillPressures) {
  // thesis-5finger's sensors: counts 1638..14745, so the span check admits 1376 and not 1375.
  h.adc.counts[2] = 1376;
  h.Run(1, true);
  LONGS_EQUAL(0, h.board->line_output(2).status & pp::line_status::kSensorFault);
  LONGS_EQUAL(0, h.board->latched_faults() & FaultBit(Fault::kImplausibleSensor));
  h.adc.counts[2] = 1375;
  h.Run(1, true);
  CHECK(h.board->line_output(2).status & pp::line_status::kSensorFault);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kImplausibleSensor));
}

TEST(BoardFaults, AFailedConversionIsNoPressure) {
  h.Run(1, true);
  LONGS_EQUAL(0, h.board->latched_faults());
  h.adc.fail = true;  // the scan delivers nothing on any channel
  h.Run(1, true);
  CHECK(h.board->line_output(0).status & pp::line_status::kSensorFault);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kImplausibleSensor));
  CHECK(h.AllLinesSafe());
}

TEST(BoardFaults, AFailedDacWriteLatchesAndTheValvesLetGo) {
  CHECK(h.supply.changes > 0);  // pulsing: the supply valve is held open
  h.dac.fail = true;            // the regulators keep their last codes
  h.Run(2, true);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kOutputWrite));
  CHECK(h.board->safe());
  const uint32_t supply = h.supply.changes, dump = h.dump.changes;
  h.Run(20, true);
  LONGS_EQUAL(supply, h.supply.changes);  // no more pulses: both valves fall back
  LONGS_EQUAL(dump, h.dump.changes);
  CHECK_FALSE(h.pump.level);
  h.Drain();
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kConditionPersists,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
  h.dac.fail = false;
  h.Run(2, true);
  CHECK(h.AllLinesSafe());  // the safe codes reach the regulators once writes work again
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
}

TEST(BoardFaults, AScanReadsEachChannelOnceAndMarksFailedOnes) {
  palpa::hal::fake::FakeAnalogInput adc;
  adc.counts[0] = 1234;
  adc.counts[1] = 0;
  uint32_t scan[3] = {};
  palpa::hal::AnalogInput& in = adc;
  in.ReadAll(scan, 3);
  LONGS_EQUAL(1234, scan[0]);
  LONGS_EQUAL(0, scan[1]);
  adc.fail = true;
  in.ReadAll(scan, 3);
  for (uint32_t c : scan) LONGS_EQUAL(palpa::hal::AnalogInput::kConversionFailed, c);
}

TEST_GROUP(BoardBoot){};

TEST(BoardBoot, WatchdogResetIsLatchedAndReported) {
  BoardHarness h("thesis-5finger", pp::ResetCause::kWatchdog);
  const pp::HelloReply r = h.Connect();
  CHECK(r.reset_cause == pp::ResetCause::kWatchdog);
  CHECK(r.fault_bitmap & FaultBit(Fault::kUnexpectedReset));
  h.Send(pp::ClearFault{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kClearFault));
}

TEST(BoardBoot, SavedConfigurationSurvivesARebootAndFactoryResetForgetsIt) {
  palpa::hal::fake::SimulatedNorFlash flash{64 * 1024, 8 * 1024};
  {
    BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
    h.Connect();
    pp::ConfigureBoard board = h.board->config().board;
    board.host_timeout_us = 250000;
    h.Send(board);
    h.Send(pp::SaveConfig{});
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kSaveConfig));
  }
  {
    BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
    const pp::HelloReply r = h.Connect();
    CHECK_FALSE(r.config_is_default);
    LONGS_EQUAL(250000, r.host_timeout_us);
    h.Send(pp::FactoryReset{});
    LONGS_EQUAL(100000, h.board->config().board.host_timeout_us);
  }
  BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
  CHECK(h.Connect().config_is_default);
}

namespace {

/// The board's Diagnostics: (saved, unsaved) — what the next boot loads, and whether the live
/// configuration differs from it.
std::pair<bool, bool> ConfigState(BoardHarness& h) {
  h.Send(pp::GetDiagnostics{});
  for (const BoardFrame& f : h.Drain()) {
    if (f.Is<pp::Diagnostics>()) {
      const auto d = f.As<pp::Diagnostics>();
      return {d.config_saved, d.config_unsaved};
    }
  }
  FAIL("no Diagnostics");
  return {};
}

}  // namespace

TEST(BoardBoot, DiagnosticsSayWhetherTheLiveConfigurationIsSaved) {
  // What `palpa info` reports: "(saved)" only when a reset would come back to this configuration.
  palpa::hal::fake::SimulatedNorFlash flash{64 * 1024, 8 * 1024};
  BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
  h.Connect();
  CHECK(ConfigState(h) == std::make_pair(false, false));  // factory, nothing saved
  pp::ConfigureBoard board = h.board->config().board;
  board.host_timeout_us = 250000;
  h.Send(board);
  CHECK(ConfigState(h) == std::make_pair(false, true));  // changed, a reset would lose it
  h.Send(pp::SaveConfig{});
  CHECK(ConfigState(h) == std::make_pair(true, false));
  board.host_timeout_us = 300000;
  h.Send(board);
  CHECK(ConfigState(h) == std::make_pair(true, true));  // a reset returns to the saved one
  h.Send(pp::FactoryReset{});
  CHECK(ConfigState(h) == std::make_pair(false, false));
  h.Send(board);  // factory reset, then set: changed, and nothing saved behind it
  CHECK(ConfigState(h) == std::make_pair(false, true));
  BoardHarness rebooted("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
  rebooted.Connect();
  CHECK(ConfigState(rebooted) == std::make_pair(false, false));
}

TEST(BoardBoot, ASavedConfigurationForAnotherDacFallsBackToTheFactoryOne) {
  palpa::hal::fake::SimulatedNorFlash flash{64 * 1024, 8 * 1024};
  {
    BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);
    h.Connect();
    h.dac.specs[0] = {16, pp::SignalRange::kVolt0To10};  // this board's line 1 has a 16-bit DAC
    pp::ConfigureLine line = h.board->config().lines[0];
    line.dac_bits = 16;
    h.Send(line);
    h.Send(pp::SaveConfig{});
    const auto frames = h.Drain();
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)BoardHarness::AnswerFor(frames, pp::MessageType::kConfigureLine));
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)BoardHarness::AnswerFor(frames, pp::MessageType::kSaveConfig));
  }
  BoardHarness h("thesis-5finger", pp::ResetCause::kPowerOn, &flash);  // the usual 12-bit DAC
  CHECK(h.Connect().config_is_default);
  LONGS_EQUAL(12, h.board->config().lines[0].dac_bits);
}

TEST_GROUP(BoardConfiguration) {
  BoardHarness h;
  void setup() override {
    h.Connect();
    h.Drain();
  }
};

TEST(BoardConfiguration, ConfigurationBeyondTheHardCeilingIsNacked) {
  pp::ConfigureLine line = h.board->config().lines[3];  // a bias line
  line.limit_max_pa = 30000;
  h.Send(line);
  const auto frames = h.Drain();
  LONGS_EQUAL((int)pp::Status::kOutOfRange,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kConfigureLine));
  LONGS_EQUAL(20000, h.board->config().lines[3].limit_max_pa);
}

TEST(BoardConfiguration, ALineMustMatchItsDac) {
  pp::ConfigureLine line = h.board->config().lines[2];
  line.dac_bits = 16;  // the DAC has 12: every command would land 16 times too low
  h.Send(line);
  LONGS_EQUAL((int)pp::Status::kBadValue,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
  line = h.board->config().lines[2];
  line.dac_signal = pp::SignalRange::kMilliamp4To20;  // the output is 0-10 V
  h.Send(line);
  LONGS_EQUAL((int)pp::Status::kBadValue,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
  LONGS_EQUAL(12, h.board->config().lines[2].dac_bits);
  CHECK(h.board->config().lines[2].dac_signal == pp::SignalRange::kVolt0To10);
  h.dac.specs[2] = {12,
                    pp::SignalRange::kMilliamp4To20};  // a board whose output 3 is a current loop
  h.Send(line);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
}

TEST(BoardConfiguration, StagedConfigurationAppliesAllOrNothing) {
  pc::BoardConfig wanted = h.board->config();
  wanted.lines[0].slew_pa_per_s = 80000;
  wanted.lines[1].slew_pa_per_s = 70000;
  std::vector<uint8_t> blob(pc::kMaxConfigBlob);
  auto n = pc::EncodeConfigBlob(wanted, blob.data(), blob.size());
  blob.resize(n.value);
  // `crc_flip` corrupts the commit's CRC; `parts` < all abandons the upload before its commit.
  auto upload = [&](const std::vector<uint8_t>& bytes, uint32_t crc_flip = 0,
                    size_t parts = SIZE_MAX) {
    h.Send(pp::StagedBegin{static_cast<uint16_t>(bytes.size())});
    for (size_t at = 0; at < bytes.size() && parts > 0; at += pp::kMaxStagedChunk, --parts) {
      pp::StagedPart part{};
      part.offset = static_cast<uint16_t>(at);
      part.data_size =
          static_cast<uint8_t>(std::min<size_t>(pp::kMaxStagedChunk, bytes.size() - at));
      std::copy(bytes.begin() + at, bytes.begin() + at + part.data_size, part.data.begin());
      h.Send(part);
    }
    if (parts == 0) return pp::Status::kOk;
    h.Send(pp::StagedCommit{static_cast<uint16_t>(bytes.size()),
                            pp::Crc32(bytes.data(), bytes.size()) ^ crc_flip});
    return BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kStagedCommit);
  };
  // A commit whose CRC is not that of the parts received: refused, nothing applied.
  LONGS_EQUAL((int)pp::Status::kCrcError, (int)upload(blob, 1u << 7));
  LONGS_EQUAL(200000, h.board->config().lines[0].slew_pa_per_s);
  upload(blob, 0, 2);  // begun and left after two parts: the next begin starts afresh
  // A blob whose last finger is invalid: none of it is applied.
  pc::BoardConfig broken = wanted;
  broken.fingers[4].bias_pa = 90000;
  std::vector<uint8_t> bad(pc::kMaxConfigBlob);
  n = pc::EncodeConfigBlob(broken, bad.data(), bad.size());
  bad.resize(n.value);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)upload(bad));
  LONGS_EQUAL(200000, h.board->config().lines[0].slew_pa_per_s);
  LONGS_EQUAL((int)pp::Status::kOk, (int)upload(blob));
  LONGS_EQUAL(80000, h.board->config().lines[0].slew_pa_per_s);
  LONGS_EQUAL(70000, h.board->config().lines[1].slew_pa_per_s);
  CHECK_FALSE(h.board->config_is_default());
}

TEST(BoardConfiguration, AChannelTheConfigurationDropsIsLeftAtItsSafeCode) {
  // The host adds an eighth line and drives it; a FactoryReset brings back the seven-line layout.
  pp::ConfigureLine extra = h.board->config().lines[0];
  extra.line = 7;
  extra.safe_pa = 0;
  h.Send(extra);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
  for (int i = 0; i < 50; ++i) {
    h.Run(1, i % 20 == 0);
    h.FollowModel();
  }
  h.Send(pp::ClearFault{});  // the new line's sensor read nothing before it was configured
  h.Send(pp::SetLineSetpoints{h.hello_nonce, 1, 1, {{{7, 40000}}}});
  for (int i = 0; i < 500; ++i) {
    h.Run(1, i % 20 == 0);
    h.FollowModel();
  }
  const uint32_t driven = h.dac.counts[7];
  CHECK(driven > 1500);  // ≈ 40 kPa on a 12-bit 0..100 kPa output
  // While the DAC's bus fails the write is retried every tick, and output_write says why.
  h.dac.fail = true;
  h.Send(pp::FactoryReset{});
  LONGS_EQUAL(7, h.board->config().line_count);
  h.Run(5, true);
  LONGS_EQUAL(driven, h.dac.counts[7]);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kOutputWrite));
  h.dac.fail = false;
  h.Run(1, true);
  LONGS_EQUAL(0, h.dac.counts[7]);
  h.Run(100, true);
  LONGS_EQUAL(0, h.dac.counts[7]);
}

TEST(BoardConfiguration, AChannelTheConfigurationDropsIsParkedAtOnce) {
  pp::ConfigureLine extra = h.board->config().lines[0];
  extra.line = 7;
  extra.safe_pa = 20000;  // a code no tick of the old configuration would leave behind by chance
  h.Send(extra);
  h.Send(pp::FactoryReset{});
  LONGS_EQUAL(7, h.board->config().line_count);
  DOUBLES_EQUAL(20000.0 / 100000 * 4095, h.dac.counts[7], 1);  // before any tick runs
}
