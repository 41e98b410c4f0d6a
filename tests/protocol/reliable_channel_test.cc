// Reliable channel end to end over a lossy, duplicating, reordering, corrupting link: every
// command applied exactly once and in order within a session, unknown outcomes across resets.
#include <algorithm>
#include <string>

#include "link_harness.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;
using palpa::testing::ChannelFaults;
using palpa::testing::LossyChannel;
using palpa::testing::TestBoard;
using palpa::testing::TestHost;

namespace {

struct Run {
  TestBoard board;
  TestHost host;
  LossyChannel to_board;
  LossyChannel to_host;
  uint64_t now_us = 0;

  Run(ChannelFaults faults, uint32_t seed, uint8_t initial_seq, uint16_t rx_buffer = 1024)
      : board(pp::kCatalogHash, rx_buffer, seed),
        host(pp::kCatalogHash, seed + 1, initial_seq),
        to_board(faults, seed + 2),
        to_host(faults, seed + 3) {}

  void Step() {
    std::vector<std::vector<uint8_t>> replies;
    board.Receive(to_board.Deliver(now_us), replies);
    for (const auto& r : replies) to_host.Send(r.data(), r.size(), now_us);
    host.Step(now_us, to_host.Deliver(now_us),
              [&](const uint8_t* f, size_t n) { to_board.Send(f, n, now_us); });
    now_us += 250;
  }

  /// Runs until every submitted command has an outcome (or the time limit).
  void RunUntilSettled(uint64_t limit_us) {
    while (now_us < limit_us) {
      Step();
      if (host.queued() == 0 && host.outcomes.size() == host.submitted_order.size() &&
          host.session.open()) {
        return;
      }
    }
    FAIL("did not settle in time");
  }
};

/// Within one boot of the board, the applied ids are exactly the ids the host submitted, in order,
/// minus those Nacked; each appears once overall.
void CheckExactlyOnceInOrder(const Run& run) {
  std::vector<uint32_t> applied;
  for (const auto& a : run.board.applied) applied.push_back(a.command_id);
  std::vector<uint32_t> sorted = applied;
  std::sort(sorted.begin(), sorted.end());
  CHECK_TEXT(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end(), "applied twice");
  CHECK_TEXT(std::is_sorted(applied.begin(), applied.end()), "applied out of order");
  for (const auto& [id, status] : run.host.outcomes) {
    const bool was_applied = std::binary_search(sorted.begin(), sorted.end(), id);
    if (status == pp::Status::kOk)
      CHECK_TEXT(was_applied, ("acked but not applied: " + std::to_string(id)).c_str());
    if (status == pp::Status::kOutOfRange) CHECK_TEXT(!was_applied, "nacked but applied");
  }
}

}  // namespace

TEST_GROUP(ReliableChannel){};

TEST(ReliableChannel, CleanLinkAppliesEveryCommandOnceInOrder) {
  Run run(ChannelFaults{}, 1, 0);
  run.host.QueueCommands(1, 1000);
  run.RunUntilSettled(60'000'000);
  LONGS_EQUAL(1000, run.board.applied.size());
  for (const auto& [id, status] : run.host.outcomes) LONGS_EQUAL((int)pp::Status::kOk, (int)status);
  CheckExactlyOnceInOrder(run);
  LONGS_EQUAL(0, run.host.sender.counters().retransmissions);
}

TEST(ReliableChannel, SurvivesLossDuplicationReorderingAndCorruption) {
  for (uint32_t seed = 10; seed < 16; ++seed) {
    ChannelFaults faults;
    faults.drop = 0.05;
    faults.duplicate = 0.05;
    faults.corrupt = 0.03;
    faults.byte_loss = 0.001;
    faults.latency_us = 400;
    faults.jitter_us = 3000;  // frames overtake each other
    Run run(faults, seed, static_cast<uint8_t>(seed * 37));
    run.host.QueueCommands(1, 1000);
    run.RunUntilSettled(600'000'000);
    LONGS_EQUAL(1000, run.host.outcomes.size());
    for (const auto& [id, status] : run.host.outcomes) {
      LONGS_EQUAL_TEXT((int)pp::Status::kOk, (int)status, std::to_string(id).c_str());
    }
    LONGS_EQUAL(1000, run.board.applied.size());
    CheckExactlyOnceInOrder(run);
    CHECK(run.host.sender.counters().retransmissions > 0);
  }
}

TEST(ReliableChannel, SequenceNumbersWrapWithoutLossOrRepeat) {
  for (int start = 240; start <= 255; ++start) {
    ChannelFaults faults;
    faults.drop = 0.02;
    Run run(faults, static_cast<uint32_t>(start), static_cast<uint8_t>(start));
    run.host.QueueCommands(1, 600);  // wraps the u8 sequence twice
    run.RunUntilSettled(300'000'000);
    LONGS_EQUAL(600, run.board.applied.size());
    CheckExactlyOnceInOrder(run);
  }
}

TEST(ReliableChannel, WindowAndBytesInFlightAreBounded) {
  Run run(ChannelFaults{}, 3, 0, 200);  // a board with a 200-byte receive buffer
  run.host.QueueCommands(1, 100);
  run.RunUntilSettled(60'000'000);
  CHECK(run.host.window_full_refusals > 0);
  CHECK(run.host.max_bytes_in_flight <= 200);
  CHECK(run.host.sender.pending() <= pp::kMaxWindow);
  CheckExactlyOnceInOrder(run);

  pp::ReliableSender sender;
  sender.Reset(0);
  for (int i = 0; i < pp::kMaxWindow; ++i) CHECK(sender.Submit(pp::ClearFault{1}, 0).ok());
  LONGS_EQUAL((int)pp::Status::kWindowFull, (int)sender.Submit(pp::ClearFault{1}, 0).status);
}

TEST(ReliableChannel, NackedCommandsAreReportedAndNotApplied) {
  ChannelFaults faults;
  faults.drop = 0.05;
  Run run(faults, 4, 100);
  run.host.QueueCommands(0, 50);  // id 0 becomes ClearFault{mask 0}: refused by the board
  run.RunUntilSettled(60'000'000);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)run.host.outcomes.at(0));
  LONGS_EQUAL(49, run.board.applied.size());
  CheckExactlyOnceInOrder(run);
}

TEST(ReliableChannel, BoardResetMidStreamReportsOutcomeUnknownAndRecovers) {
  for (uint32_t seed = 20; seed < 30; ++seed) {
    ChannelFaults faults;
    faults.drop = 0.02;
    faults.jitter_us = 500;
    Run run(faults, seed, 250);
    run.host.QueueCommands(1, 400);
    const uint64_t reset_at = 20'000 + (seed - 20) * 7'000;
    while (run.now_us < reset_at) run.Step();
    const size_t before = run.board.applied.size();
    run.board.Reboot();
    run.RunUntilSettled(300'000'000);
    CHECK(run.host.resets_seen >= 1);
    LONGS_EQUAL(400, run.host.outcomes.size());
    size_t unknown = 0;
    for (const auto& [id, status] : run.host.outcomes) {
      CHECK(status == pp::Status::kOk || status == pp::Status::kOutcomeUnknown);
      unknown += status == pp::Status::kOutcomeUnknown;
    }
    CHECK(before < 400);
    CheckExactlyOnceInOrder(run);
    // Commands acked were applied; of the unknown ones, some were (before the reset), some not.
    size_t unknown_applied = 0;
    for (const auto& a : run.board.applied) {
      unknown_applied += run.host.outcomes.at(a.command_id) == pp::Status::kOutcomeUnknown;
    }
    LONGS_EQUAL(400 - unknown + unknown_applied, run.board.applied.size());
  }
}

TEST(ReliableChannel, HostRestartOpensAFreshSession) {
  ChannelFaults faults;
  faults.drop = 0.02;
  Run run(faults, 40, 7);
  run.host.QueueCommands(1, 200);
  while (run.board.applied.size() < 50) run.Step();
  // The host process dies: a new one (new nonce, new initial seq) talks to the same board.
  TestHost fresh(pp::kCatalogHash, 999, 200);
  fresh.QueueCommands(10001, 200);
  LossyChannel to_board(faults, 41), to_host(faults, 42);
  uint64_t now = run.now_us + 1'000'000;  // stale frames of the dead host are long gone
  run.board.SilenceEndsTheSession();      // and so is its session, by the board's timeout
  const size_t old_applied = run.board.applied.size();
  while (fresh.outcomes.size() < 200 && now < run.now_us + 120'000'000) {
    std::vector<std::vector<uint8_t>> replies;
    run.board.Receive(to_board.Deliver(now), replies);
    for (const auto& r : replies) to_host.Send(r.data(), r.size(), now);
    fresh.Step(now, to_host.Deliver(now),
               [&](const uint8_t* f, size_t n) { to_board.Send(f, n, now); });
    now += 250;
  }
  LONGS_EQUAL(200, fresh.outcomes.size());
  LONGS_EQUAL(old_applied + 200, run.board.applied.size());
  for (size_t i = 0; i < 200; ++i)
    LONGS_EQUAL(10001 + i, run.board.applied[old_applied + i].command_id);
  LONGS_EQUAL(2, run.board.sessions);
}

TEST_GROUP(LatestWins){};

TEST(LatestWins, OnlyNewerGenerationsApplyAcrossWrap) {
  pp::GenerationGate gate;
  CHECK(gate.Accept(0xFFFFFFF0u));
  CHECK_FALSE(gate.Accept(0xFFFFFFF0u));
  CHECK_FALSE(gate.Accept(0xFFFFFF00u));
  CHECK(gate.Accept(0xFFFFFFFFu));
  CHECK(gate.Accept(3));  // wrapped: newer
  CHECK_FALSE(gate.Accept(0xFFFFFFFEu));
  LONGS_EQUAL(3, gate.applied());
  LONGS_EQUAL(3, gate.dropped());
  gate.Reset();
  CHECK(gate.Accept(1));  // a new session starts afresh
}

TEST(LatestWins, ReorderedStreamConvergesToTheLatestValue) {
  ChannelFaults faults;
  faults.drop = 0.1;
  faults.duplicate = 0.1;
  faults.jitter_us = 5000;
  LossyChannel link(faults, 77);
  TestBoard board(pp::kCatalogHash, 1024, 78);
  std::vector<std::vector<uint8_t>> ignored;
  uint8_t frame[pp::kMaxFrameSize];
  auto n = pp::EncodeMessageFrame(pp::Hello{5, 0}, 0, 0, frame, sizeof(frame));
  board.Receive(std::vector<uint8_t>(frame, frame + n.value), ignored);
  uint64_t now = 0;
  uint32_t last_seen = 0;
  for (uint32_t g = 1; g <= 2000; ++g, now += 100) {
    n = pp::EncodeMessageFrame(pp::Heartbeat{5, g}, 0, 0, frame, sizeof(frame));
    link.Send(frame, n.value, now);
    board.Receive(link.Deliver(now), ignored);
    CHECK(board.applied_heartbeat() >= last_seen);  // never goes backwards
    last_seen = board.applied_heartbeat();
  }
  // The sender repeats the latest until it is applied, as the host library does.
  for (int i = 0; i < 100 && board.applied_heartbeat() != 2000; ++i, now += 1000) {
    link.Send(frame, n.value, now);
    board.Receive(link.Deliver(now + 10000), ignored);
  }
  LONGS_EQUAL(2000, board.applied_heartbeat());
}

TEST(ReliableChannel, AnAnswerToAResentCommandKeepsTheBackOff) {
  // Karn: only an answer to a command sent once is a round-trip sample and drops the back-off.
  pp::ReliableSender sender;
  sender.Reset(0);
  auto ignore = [](const uint8_t*, size_t) {};
  auto outcome = [](const pp::CommandOutcome&) {};
  CHECK(sender.Submit(pp::ClearFault{1}, 1).ok());
  sender.Transmit(0, ignore);
  sender.OnAnswer(0, pp::Status::kOk, 0, 1000, outcome);  // a clean 1 ms round trip
  const uint32_t base = sender.rto_us();
  CHECK(sender.Submit(pp::ClearFault{1}, 2).ok());
  sender.Transmit(10000, ignore);
  sender.Transmit(10000 + base + 1, ignore);  // timed out: resent, the timeout doubled
  const uint32_t backed_off = sender.rto_us();
  CHECK(backed_off > base);
  sender.OnAnswer(1, pp::Status::kOk, 0, 10000 + base + 2000, outcome);
  LONGS_EQUAL(backed_off, sender.rto_us());  // which transmission was answered is unknown
  CHECK(sender.Submit(pp::ClearFault{1}, 3).ok());
  sender.Transmit(100000, ignore);
  sender.OnAnswer(2, pp::Status::kOk, 0, 101000, outcome);  // sent once: a sample
  CHECK(sender.rto_us() < backed_off);
}

TEST(ReliableChannel, RoomIsCountedInBytesAsWellAsCommands) {
  pp::SenderConfig config;
  config.max_bytes_in_flight = 600;
  pp::ReliableSender sender(config);
  sender.Reset(0);
  pp::UpdateWrite w;
  w.data_size = 240;
  CHECK(sender.HasRoomFor(246));
  CHECK(sender.Submit(w, 1).ok());
  CHECK(sender.HasRoomFor(246));
  CHECK(sender.Submit(w, 2).ok());
  CHECK_FALSE(sender.HasRoomFor(246));  // a third would overrun the board's receive buffer
  CHECK(sender.HasRoomFor(2));          // a small command still fits
  LONGS_EQUAL((int)pp::Status::kWindowFull, (int)sender.Submit(w, 3).status);
}
