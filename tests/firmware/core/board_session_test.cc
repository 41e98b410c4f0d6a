// Sessions on the board: Close and Release end actuation without a fault, only fresh frames of
// the commanding session keep the host-silence timer, a second host is told busy, and silence is
// a fault only where the host left the board actuated.
#include <initializer_list>
#include <string>
#include <vector>

#include "board_harness.h"
#include "palpa/core/flash_layout.h"
#include "palpa/protocol/faults.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::BoardHarness;
namespace pp = palpa::protocol;
namespace pc = palpa::core;
using pp::Fault;
using pp::FaultBit;

namespace {

constexpr uint32_t kTimeoutMs = 100;  // thesis-5finger's host-silence timeout

pp::SetLineSetpoints Setpoints(uint32_t generation, int32_t pa, uint32_t session = 0) {
  pp::SetLineSetpoints m{};
  m.session = session;  // 0: the harness's own session
  m.generation = generation;
  m.entry_count = 1;
  m.entries[0] = {0, pa};
  return m;
}

/// Runs `ms` ticks with the plant following the regulator model, heartbeating when asked.
void Follow(BoardHarness& h, uint32_t ms, bool heartbeat) {
  for (uint32_t i = 0; i < ms; ++i) {
    h.Run(1, heartbeat && i % 20 == 0);
    h.FollowModel();
  }
}

/// A session with line 0 at 30 kPa, heartbeats keeping it; what the board sent so far is read.
void ActuateLine0(BoardHarness& h) {
  h.Connect();
  h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
  h.Send(Setpoints(1, 30000));
  Follow(h, 300, true);
  h.Drain();
}

/// The answer the board gave to the last message of `type` sent, from what it sent since.
pp::Status Answer(BoardHarness& h, pp::MessageType type) {
  return BoardHarness::AnswerFor(h.Drain(), type);
}

}  // namespace

TEST_GROUP(BoardClose) {
  BoardHarness h;
  void Actuate() {
    ActuateLine0(h);
    CHECK_FALSE(h.board->safe());
    CHECK_FALSE(h.AllLinesSafe());
  }
};

TEST(BoardClose, CloseMakesEveryOutputSafeWithinATickLatchesNothingAndEndsTheSession) {
  Actuate();
  h.Send(pp::Close{});
  const auto answers = h.Drain();
  LONGS_EQUAL((int)pp::Status::kOk, (int)BoardHarness::AnswerFor(answers, pp::MessageType::kClose));
  for (const auto& f : answers) {
    if (f.Is<pp::Ack>()) LONGS_EQUAL(0xB0075EED, f.As<pp::Ack>().boot_nonce);
  }
  CHECK_FALSE(h.board->session_open());
  h.Run(1);
  CHECK(h.AllLinesSafe());
  CHECK(h.board->safe());
  Follow(h, 5 * kTimeoutMs, false);  // and silence afterwards is no fault either
  LONGS_EQUAL(0, h.board->latched_faults());
  // Later frames of that session get no_session; a repeated Close is answered the same way.
  h.Send(Setpoints(2, 30000));
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)Answer(h, pp::MessageType::kSetLineSetpoints));
  h.Send(pp::Close{});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)Answer(h, pp::MessageType::kClose));
  // The next host opens a session at once.
  CHECK(h.Connect().boot_nonce == 0xB0075EED);
  CHECK(h.board->session_open());
}

TEST(BoardClose, AnotherSessionsCloseOrReleaseChangesNothing) {
  Actuate();
  h.Send(pp::Close{h.hello_nonce + 1});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)Answer(h, pp::MessageType::kClose));
  h.Send(pp::Release{h.hello_nonce + 1});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)Answer(h, pp::MessageType::kRelease));
  Follow(h, 50, true);
  CHECK(h.board->session_open());
  CHECK_FALSE(h.AllLinesSafe());
}

TEST(BoardClose, ReleaseMakesEveryOutputSafeAndKeepsTheSession) {
  Actuate();
  h.Send(pp::Release{});
  LONGS_EQUAL((int)pp::Status::kOk, (int)Answer(h, pp::MessageType::kRelease));
  h.Run(1);
  CHECK(h.AllLinesSafe());
  CHECK(h.board->session_open());
  Follow(h, 5 * kTimeoutMs, true);  // the session goes on, safe, without a fault
  CHECK(h.AllLinesSafe());
  LONGS_EQUAL(0, h.board->latched_faults());
  h.Send(Setpoints(2, 30000));  // and actuates again when told to
  Follow(h, 300, true);
  CHECK_FALSE(h.AllLinesSafe());
}

TEST(BoardClose, AfterAReleaseSilenceEndsTheSessionQuietly) {
  Actuate();
  h.Send(pp::Release{});
  h.Drain();
  Follow(h, 3 * kTimeoutMs, false);
  CHECK_FALSE(h.board->session_open());
  LONGS_EQUAL(0, h.board->latched_faults());
}

TEST(BoardClose, ACloseDuringAnUpdateLeavesTheLinesSafeAndTheImageResumable) {
  palpa::hal::fake::SimulatedNorFlash image_flash(pc::kDefaultLayout.total,
                                                  pc::kDefaultLayout.sector_size);
  pc::UpdateEngine engine(&image_flash, pc::kDefaultLayout, pp::BoardKind::kSim, 0);
  BoardHarness u("thesis-5finger", pp::ResetCause::kPowerOn, nullptr, &engine);
  u.Connect();
  const uint8_t slot = engine.inactive_slot();
  u.Send(pp::UpdateEnter{slot, 4096});
  u.Send(pp::UpdateErase{slot, 0, 8192});
  pp::UpdateWrite w{slot, 0, 64, {}};
  u.Send(w);
  CHECK(engine.in_update_mode());
  LONGS_EQUAL(64, engine.Query(slot).written_bytes);
  u.Send(pp::Close{});
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)BoardHarness::AnswerFor(u.Drain(), pp::MessageType::kClose));
  CHECK_FALSE(engine.in_update_mode());
  u.Run(1);
  CHECK(u.AllLinesSafe());
  LONGS_EQUAL(0, u.board->latched_faults());
  // The next session resumes where the update stopped.
  u.Connect();
  u.Send(pp::UpdateEnter{slot, 4096});
  LONGS_EQUAL(64, engine.Query(slot).written_bytes);
}

TEST_GROUP(BoardBusy) { BoardHarness h; };

TEST(BoardBusy, ASecondHostsHelloIsAnsweredBusyAndTakesNothing) {
  h.Connect();
  h.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
  h.Send(Setpoints(1, 30000));
  Follow(h, 200, true);
  h.Drain();
  h.Send(pp::Hello{0xFEED, 9});
  const auto answers = h.Drain();
  bool busy = false;
  for (const auto& f : answers) {
    CHECK_FALSE(f.Is<pp::HelloReply>());
    if (f.Is<pp::Nack>()) {
      const auto n = f.As<pp::Nack>();
      LONGS_EQUAL((int)pp::MessageType::kHello, n.refused_type);
      LONGS_EQUAL((int)pp::Status::kBusy, (int)n.status);
      LONGS_EQUAL(100000, n.detail);  // when a silent session would end
      busy = true;
    }
  }
  CHECK(busy);
  // The first host goes on: its heartbeats and setpoints still count.
  h.Send(Setpoints(2, 40000));
  Follow(h, 300, true);
  CHECK_FALSE(h.AllLinesSafe());
  LONGS_EQUAL(0, h.board->latched_faults());
  // Its frames the second host might send are not applied.
  h.Send(Setpoints(100, 90000, 0xFEED));
  Follow(h, 50, true);
  CHECK(h.CommandedPa(0) < 45000);
  std::vector<float> before;
  for (uint8_t i = 0; i < h.board->config().line_count; ++i) before.push_back(h.CommandedPa(i));
  pp::SetFingerTargets t{};
  t.session = 0xFEED;
  t.generation = 100;
  t.entry_count = 1;
  t.entries[0] = {3, pp::OutputUnit::kStiffnessMilliNewtonPerMm, 900};  // a jamming finger
  h.Send(t);
  Follow(h, 50, true);
  for (uint8_t i = 0; i < h.board->config().line_count; ++i)
    DOUBLES_EQUAL(before[i], h.CommandedPa(i), 1.0);
}

TEST(BoardBusy, TheSessionsOwnHelloRetriedBeforeItWasHeardIsAnsweredAgain) {
  h.Send(pp::Hello{77, 0});
  h.Send(pp::Hello{77, 0});  // the reply was lost: the host asks again
  int replies = 0;
  for (const auto& f : h.Drain()) replies += f.Is<pp::HelloReply>();
  LONGS_EQUAL(2, replies);
  h.Send(pp::Heartbeat{77, 1});  // now the host has it
  h.Send(pp::Hello{77, 0});      // the same nonce again is someone else
  LONGS_EQUAL((int)pp::Status::kBusy, (int)Answer(h, pp::MessageType::kHello));
}

TEST(BoardBusy, ABusyBoardIsFreeOnceTheSilentHostsSessionEnds) {
  h.Connect();
  Follow(h, 50, true);
  h.Send(pp::Hello{0xFEED, 0});
  LONGS_EQUAL((int)pp::Status::kBusy, (int)Answer(h, pp::MessageType::kHello));
  Follow(h, kTimeoutMs + 2, false);  // the first host is gone
  CHECK_FALSE(h.board->session_open());
  LONGS_EQUAL(0, h.board->latched_faults());  // it left nothing actuated
  h.Send(pp::Hello{0xFEED, 0});
  bool reply = false;
  for (const auto& f : h.Drain()) reply |= f.Is<pp::HelloReply>();
  CHECK(reply);
}

TEST_GROUP(BoardSilence) {
  BoardHarness h;
  void Actuate() { ActuateLine0(h); }
  /// Sends `frame_of(i)` every 10 ms for `ms`; true when the line stayed actuated throughout.
  template <class F>
  bool KeptActuatedBy(uint32_t ms, F && frame_of) {
    for (uint32_t i = 0; i < ms; ++i) {
      if (i % 10 == 0) frame_of(i);
      h.Run(1);
      h.FollowModel();
      if (h.AllLinesSafe()) return false;
    }
    return true;
  }
};

TEST(BoardSilence, ARepeatedHeartbeatKeepsNothingAlive) {
  Actuate();
  const uint32_t generation = ++h.generation;
  CHECK_FALSE(KeptActuatedBy(3 * kTimeoutMs, [&](uint32_t) {
    h.Send(pp::Heartbeat{h.hello_nonce, generation}, false);  // stale after the first
  }));
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
}

TEST(BoardSilence, AnotherSessionsHeartbeatsKeepNothingAlive) {
  Actuate();
  uint32_t g = 1000;
  CHECK_FALSE(KeptActuatedBy(3 * kTimeoutMs, [&](uint32_t) {
    h.Send(pp::Heartbeat{h.hello_nonce + 1, ++g}, false);
  }));
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
}

TEST(BoardSilence, EmptyHeartbeatsAndBoardFramesKeepNothingAlive) {
  Actuate();
  CHECK_FALSE(KeptActuatedBy(3 * kTimeoutMs, [&](uint32_t i) {
    uint8_t packet[pp::kHeaderSize];
    const uint8_t type = i % 20 == 0 ? static_cast<uint8_t>(pp::MessageType::kHeartbeat)
                                     : static_cast<uint8_t>(pp::MessageType::kTelemetry);
    pp::WriteHeader(pp::Header{pp::kProtocolVersion, type, 0, 0}, packet);
    uint8_t frame[pp::kMaxFrameSize];
    const auto n = pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame));
    h.link.Inject(frame, n.value);
  }));
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
}

TEST(BoardSilence, RepeatedStreamFramesKeepNothingAlive) {
  Actuate();
  const pp::SetLineSetpoints same = Setpoints(1, 30000);  // applied already
  CHECK_FALSE(KeptActuatedBy(3 * kTimeoutMs, [&](uint32_t) { h.Send(same); }));
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
}

TEST(BoardSilence, FreshFramesOfTheSessionKeepItAlive) {
  Actuate();
  uint32_t g = 1;
  CHECK(KeptActuatedBy(10 * kTimeoutMs, [&](uint32_t i) {
    if (i % 30 == 0) h.Send(pp::Heartbeat{h.hello_nonce, ++h.generation}, false);
    if (i % 30 == 10) h.Send(Setpoints(++g, 30000));
    if (i % 30 == 20) h.Send(pp::GetLoopStats{});
  }));
  LONGS_EQUAL(0, h.board->latched_faults());
}

TEST(BoardSilence, AppliedReliableCommandsAloneKeepItAlive) {
  Actuate();
  CHECK(KeptActuatedBy(10 * kTimeoutMs, [&](uint32_t i) {
    if (i % 50 == 0) h.Send(pp::GetLoopStats{});  // each with the next seq: applied once
  }));
  LONGS_EQUAL(0, h.board->latched_faults());
}

TEST(BoardSilence, ASessionThatLeftTheBoardSafeEndsQuietly) {
  h.Connect();
  h.Send(pp::GetDiagnostics{});  // a host that only reads
  Follow(h, 3 * kTimeoutMs, false);
  CHECK_FALSE(h.board->session_open());
  LONGS_EQUAL(0, h.board->latched_faults());
}

TEST(BoardSilence, AClearThenSilenceIsNoNewFault) {
  Actuate();
  Follow(h, 2 * kTimeoutMs, false);  // the host vanished while actuating: a fault
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
  h.Connect();
  h.Send(pp::ClearFault{});  // cleared, nothing applied since: the board is safe
  LONGS_EQUAL((int)pp::Status::kOk, (int)Answer(h, pp::MessageType::kClearFault));
  Follow(h, 2 * kTimeoutMs, false);
  CHECK_FALSE(h.board->session_open());
  LONGS_EQUAL(0, h.board->latched_faults());
}

TEST(BoardSilence, AJammingFingersBiasCountsAsActuated) {
  h.Connect();
  pp::SetFingerTargets t{};
  t.generation = 1;
  t.entry_count = 1;
  t.entries[0] = {3, pp::OutputUnit::kStiffnessMilliNewtonPerMm, 0};  // stiffness 0: bias only
  h.Send(t);
  Follow(h, 2 * kTimeoutMs, false);
  CHECK(h.board->latched_faults() & FaultBit(Fault::kHostSilence));
}

TEST(BoardSilence, ABoardWithNoSessionNeverLatchesHostSilence) {
  Follow(h, 100 * kTimeoutMs, false);
  LONGS_EQUAL(0, h.board->latched_faults());
}

// HID carries a sample every few ticks: the last frame of a session that fell silent still shows
// the tick the fault latched in, every line safe, since nothing follows it.
TEST(BoardSilence, TheLastTelemetryOfASilentSessionShowsEveryLineSafeWhateverTheDecimation) {
  for (uint16_t decimation : {1, 2, 3, 4, 7}) {
    BoardHarness board;
    board.Connect();
    pp::ConfigureBoard configured = board.board->config().board;
    configured.telemetry_decimation = decimation;
    board.Send(configured);
    LONGS_EQUAL((int)pp::Status::kOk,
                (int)BoardHarness::AnswerFor(board.Drain(), pp::MessageType::kConfigureBoard));
    board.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw});
    board.Send(Setpoints(1, 30000));
    Follow(board, 301, true);
    board.Drain();
    Follow(board, 3 * kTimeoutMs, false);
    CHECK(board.board->latched_faults() & FaultBit(Fault::kHostSilence));
    CHECK_FALSE(board.board->session_open());
    pp::Telemetry last{};
    uint64_t previous_last_us = 0;
    for (const auto& f : board.Drain()) {
      if (!f.Is<pp::Telemetry>()) continue;
      last = f.As<pp::Telemetry>();
      // In the order they were taken, each frame's samples after the frame before's.
      CHECK_TEXT(last.first_sample_us > previous_last_us, std::to_string(decimation).c_str());
      previous_last_us = last.first_sample_us + (last.tick_count - 1u) * last.sample_interval_us;
    }
    CHECK_TEXT(last.fault_bitmap & FaultBit(Fault::kHostSilence),
               std::to_string(decimation).c_str());
    const uint32_t last_tick = (last.tick_count - 1u) * last.line_count;
    for (uint8_t i = 0; i < last.line_count; ++i) {
      CHECK_TEXT(
          last.samples[last_tick + i].status & pp::line_status::kSafe,
          ("decimation " + std::to_string(decimation) + ", line " + std::to_string(i + 1)).c_str());
    }
  }
}
