// The board through its link, on fakes: session, setpoints and targets, refusal rules, faults,
// clearing, configuration, telemetry, outputs.
#include <random>

#include "board_harness.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::BoardFrame;
using palpa::testing::BoardHarness;
namespace pp = palpa::protocol;
namespace pc = palpa::core;

namespace {

pp::SetLineSetpoints Setpoints(uint32_t generation,
                               std::initializer_list<pp::LineSetpoint> entries) {
  pp::SetLineSetpoints m{};
  m.generation = generation;
  for (const auto& e : entries) m.entries[m.entry_count++] = e;
  return m;
}

pp::SetFingerTargets Targets(uint32_t generation, std::initializer_list<pp::FingerTarget> entries) {
  pp::SetFingerTargets m{};
  m.generation = generation;
  for (const auto& e : entries) m.entries[m.entry_count++] = e;
  return m;
}

constexpr auto kUm = pp::OutputUnit::kDeformationMicrometre;
constexpr auto kStiff = pp::OutputUnit::kStiffnessMilliNewtonPerMm;

}  // namespace

TEST_GROUP(BoardSession) { BoardHarness h; };

TEST(BoardSession, HelloReportsTheBoard) {
  const pp::HelloReply r = h.Connect();
  LONGS_EQUAL(0xB0075EED, r.boot_nonce);
  LONGS_EQUAL(pp::kCatalogHash, r.catalog_hash);
  STRCMP_EQUAL("thesis-5finger", r.config_name.data());
  CHECK(r.config_is_default);
  CHECK(r.plant_simulated);
  LONGS_EQUAL(7, r.line_count);
  LONGS_EQUAL(5, r.finger_count);
  CHECK(r.lines[5].kind == pp::LineKind::kVacuum);
  LONGS_EQUAL(100000, r.host_timeout_us);
}

TEST(BoardSession, EverythingButHelloAndEStopIsRefusedBeforeHello) {
  h.Send(Setpoints(1, {{0, 1000}}));
  h.Send(pp::GetDiagnostics{});
  const auto frames = h.Drain();
  LONGS_EQUAL((int)pp::Status::kNoSession,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kSetLineSetpoints));
  LONGS_EQUAL((int)pp::Status::kNoSession,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kGetDiagnostics));
  h.Send(pp::EStop{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kEStop));
}

TEST(BoardSession, DuplicateReliableCommandIsAnsweredAgainNotReapplied) {
  h.Connect();
  h.Send(pp::SaveConfig{});
  h.next_seq = 0;  // the same seq again, as after a lost Ack
  h.Send(pp::SaveConfig{});
  const auto frames = h.Drain();
  int acks = 0;
  for (const auto& f : frames) acks += f.Is<pp::Ack>();
  LONGS_EQUAL(2, acks);
  palpa::hal::fake::SimulatedNorFlash* flash = h.flash;
  LONGS_EQUAL(1, flash->erases());  // saved once
}

TEST(BoardSession, TelemetryBatchesTicksAndEchoesGenerations) {
  h.Connect();
  h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
  h.Send(Setpoints(7, {{0, 20000}}));
  h.Drain();
  h.Run(20, true);
  int telemetry = 0;
  for (const auto& f : h.Drain()) {
    if (!f.Is<pp::Telemetry>()) continue;
    const auto t = f.As<pp::Telemetry>();
    LONGS_EQUAL(7, t.line_count);
    LONGS_EQUAL(2, t.tick_count);
    LONGS_EQUAL(14, t.sample_count);
    LONGS_EQUAL(7, t.setpoint_generation);
    LONGS_EQUAL(0xB0075EED, t.boot_nonce);
    ++telemetry;
  }
  CHECK(telemetry >= 9);
}

TEST_GROUP(BoardSetpoints) {
  BoardHarness h;
  void setup() override {
    h.Connect();
    h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
    h.Send(pp::SetFingerMode{3, pp::FingerMode::kRaw});
    h.Drain();
  }
};

TEST(BoardSetpoints, RawSetpointReachesTheDacAfterTheSlew) {
  h.Send(Setpoints(1, {{0, 30000}}));
  for (int i = 0; i < 400; ++i) {
    h.Run(1, i % 20 == 0);
    h.FollowModel();
  }
  DOUBLES_EQUAL(30000.0 / 100000 * 4095, h.dac.counts[0], 3);
  CHECK_FALSE(h.board->safe());
}

TEST(BoardSetpoints, ALinesRegulatorCorrectionSetsItsCommandInTheTick) {
  // Open loop (no sensor), so the steady command is the feed-forward alone: the correction's
  // command for the setpoint (the line stage has a loop without the lookup for boards whose lines
  // have no correction; this board has one).
  pp::ConfigureLine c = h.board->config().lines[0];
  c.sensor = pp::SensorKind::kNone;
  c.correction_count = 3;
  c.correction[0] = {10000, 9000, 9500};
  c.correction[1] = {50000, 48000, 49000};
  c.correction[2] = {90000, 88000, 89000};
  h.Send(c);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
  h.Send(Setpoints(1, {{0, 30000}}));
  h.Run(400, true);
  CHECK_FALSE(h.board->safe());
  DOUBLES_EQUAL(30000, h.board->line_state(0).slewed_pa, 0);
  const pc::LineParams p = pc::MakeLineParams(c, pc::Board::kTickUs);
  const float corrected = pc::CorrectionCommand(p.correction, p.correction.rising, 30000);
  CHECK(corrected > 30500);  // the regulator falls short of its command: asked for more
  DOUBLES_EQUAL(corrected, h.board->line_output(0).command_pa, 0);
}

TEST(BoardSetpoints, OutOfLimitSetpointIsNackedNeverClamped) {
  h.Send(Setpoints(1, {{0, 10000}, {3, 30000}}));  // line 3 is a bias line: 20 kPa at most
  const auto frames = h.Drain();
  LONGS_EQUAL((int)pp::Status::kOutOfRange,
              (int)BoardHarness::AnswerFor(frames, pp::MessageType::kSetLineSetpoints));
  for (const auto& f : frames) {
    if (f.Is<pp::Nack>()) LONGS_EQUAL(1, f.As<pp::Nack>().detail);  // the offending entry
  }
  h.Run(50, true);
  LONGS_EQUAL(0, h.dac.counts[0]);  // nothing of the message applied: still safe
  CHECK(h.board->safe());
}

TEST(BoardSetpoints, LinesOfAFingerInTargetModeRefuseRawSetpoints) {
  h.Send(Setpoints(1, {{1, 10000}}));
  LONGS_EQUAL((int)pp::Status::kWrongMode,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kSetLineSetpoints));
}

TEST(BoardSetpoints, OlderGenerationsAreDropped) {
  h.Send(Setpoints(5, {{0, 20000}}));
  h.Send(Setpoints(4, {{0, 50000}}));
  h.Run(300, true);
  DOUBLES_EQUAL(20000, h.board->line_state(0).slewed_pa, 1);
}

TEST(BoardSetpoints, ARawFingersLinesSayRawInAndOutOfTheSafeStateUntilItReturns) {
  namespace ls = pp::line_status;
  h.Run(2, true);  // safe: no setpoints yet
  CHECK(h.board->line_output(0).status & ls::kSafe);
  CHECK(h.board->line_output(0).status & ls::kRaw);
  CHECK(h.board->line_output(3).status & ls::kRaw);  // finger 3's bias and vacuum lines
  CHECK(h.board->line_output(5).status & ls::kRaw);
  CHECK_FALSE(h.board->line_output(1).status & ls::kRaw);  // finger 1 is in target mode
  h.Send(Setpoints(1, {{0, 10000}}));
  h.Run(2, true);
  CHECK_FALSE(h.board->safe());
  CHECK(h.board->line_output(0).status & ls::kRaw);
  h.Send(pp::SetFingerMode{0, pp::FingerMode::kTarget});
  h.Run(2, true);
  CHECK_FALSE(h.board->line_output(0).status & ls::kRaw);
  CHECK(h.board->line_output(5).status & ls::kRaw);
  // A new configuration keeps the modes, and with them the bits.
  h.Send(h.board->config().lines[2]);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureLine));
  h.Run(2, true);
  CHECK(h.board->line_output(3).status & ls::kRaw);
  CHECK_FALSE(h.board->line_output(0).status & ls::kRaw);
}

TEST_GROUP(BoardTargets) {
  BoardHarness h;
  void setup() override {
    h.Connect();
    h.Drain();
  }
};

TEST(BoardTargets, PneumaticTargetGoesThroughTheStaticInverseAfterHoming) {
  h.Send(Targets(1, {{0, kUm, 1000}}));
  h.Run(100, true);
  DOUBLES_EQUAL(0, h.board->line_state(0).slewed_pa, 0);  // homing: vented for 300 ms
  h.Run(500, true);
  DOUBLES_EQUAL(26415, h.board->line_state(0).slewed_pa, 2);
}

TEST(BoardTargets, JammingTargetHoldsTheBiasAndSetsTheVacuum) {
  h.Send(Targets(1, {{3, kStiff, 1000}}));
  h.Run(1000, true);
  DOUBLES_EQUAL(20000, h.board->line_state(3).slewed_pa, 1);
  DOUBLES_EQUAL(-50000, h.board->line_state(5).slewed_pa, 1);
  CHECK(h.pump.level);
}

TEST(BoardTargets, WrongUnitAndBeyondTheCurveAreRefused) {
  h.Send(Targets(1, {{3, kUm, 1000}}));
  LONGS_EQUAL((int)pp::Status::kBadValue,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kSetFingerTargets));
  h.Send(Targets(2, {{0, kUm, 5000}}));
  LONGS_EQUAL((int)pp::Status::kOutOfRange,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kSetFingerTargets));
  h.Send(Targets(3, {{7, kUm, 100}}));
  LONGS_EQUAL((int)pp::Status::kNotFound,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kSetFingerTargets));
}

TEST(BoardTargets, ValvesArePulsedOnlyWhileNotSafe) {
  h.Run(10, true);
  LONGS_EQUAL(0, h.supply.changes);
  CHECK_FALSE(h.dump.level);
  h.Send(Targets(1, {{0, kUm, 500}}));
  h.Run(10, true);
  CHECK(h.supply.changes >= 9);  // toggling holds the shut-off open and the dump closed
  CHECK(h.dump.changes >= 9);
  h.Send(pp::EStop{});
  h.Run(2);
  const uint32_t changes = h.supply.changes;
  h.Run(10);
  LONGS_EQUAL(changes, h.supply.changes);
  CHECK_FALSE(h.supply.level);
  CHECK_FALSE(h.pump.level);
}

TEST(BoardTargets, PiCompensatorDrivesTheLineAndSaysWhenItSaturates) {
  // y = 0.03 µm/Pa·u + 0.01·play(u, 20 kPa): a loop the static inverse knows nothing of.
  pp::ConfigureFinger f = h.board->config().fingers[0];
  f.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  f.param_count = 4;
  f.params[0] = 0;
  f.params[1] = 0.03f;
  f.params[2] = 20000;
  f.params[3] = 0.01f;
  h.Send(f);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureFinger));
  auto run = [this](int ms) {
    for (int i = 0; i < ms; ++i) {
      h.Run(1, true);
      h.FollowModel();  // the sensor reads what the regulator model predicts
    }
  };
  h.Send(Targets(1, {{0, kUm, 1000}}));
  run(1500);
  // Rising from vented: the operator stays on its upper clamp until 40 kPa, so 0.03·u + 200 = 1000.
  DOUBLES_EQUAL(26667, h.board->line_state(0).slewed_pa, 2);
  CHECK_FALSE(h.board->line_output(0).status & pp::line_status::kSaturated);
  h.Send(Targets(2, {{0, kUm, 4300}}));  // within the static inverse; the model reaches 3 800
  run(1500);
  CHECK(h.board->line_output(0).status & pp::line_status::kSaturated);
  CHECK(h.board->line_state(0).slewed_pa <= h.board->config().lines[0].limit_max_pa);
  // Safe, the line no longer follows the compensator and stops saying it saturates.
  h.Send(pp::EStop{});
  h.Run(2, true);
  CHECK(h.board->line_output(0).status & pp::line_status::kSafe);
  CHECK_FALSE(h.board->line_output(0).status & pp::line_status::kSaturated);
}

TEST(BoardTargets, CompensatorParametersThatCannotBeInvertedAreNackedAndNothingChanges) {
  pp::ConfigureFinger f = h.board->config().fingers[0];
  f.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  f.param_count = 6;
  const float params[] = {0, 0.04f, 0, 20000, 0.01f, -0.06f};  // cumulative weight < 0
  for (int i = 0; i < 6; ++i) f.params[i] = params[i];
  h.Send(f);
  LONGS_EQUAL((int)pp::Status::kBadValue,
              (int)BoardHarness::AnswerFor(h.Drain(), pp::MessageType::kConfigureFinger));
  CHECK(h.board->config().fingers[0].compensator == pp::CompensatorKind::kNone);
}
