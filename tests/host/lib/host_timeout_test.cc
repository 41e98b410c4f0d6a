// The host-silence timeout the host follows through a session, and the heartbeat period from it.
#include "palpa/host/host_timeout.h"

#include <algorithm>
#include <vector>

#include "config_record.h"
#include "palpa/protocol/crc32.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

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

namespace {

/// A staged blob's records as the board reads them.
template <class M>
void AppendRecord(std::vector<uint8_t>& blob, const M& message) {
  CHECK(palpa::testing::AppendConfigRecord(blob, message));
}

/// What `carried` reads from `message` queued as a command (its encoded body, as the link has it).
template <class M>
std::optional<uint32_t> Queue(ph::CarriedHostTimeout& carried, const M& message) {
  uint8_t body[pp::kMaxBodySize];
  const auto size = pp::EncodeBody(message, body, sizeof(body));
  CHECK(size.ok());
  return carried.Carried(static_cast<uint8_t>(M::kInfo.type), body, size.value);
}

/// Stages `blob` in chunks, as a host would; nothing is carried until the commit.
void Stage(ph::CarriedHostTimeout& carried, const std::vector<uint8_t>& blob) {
  CHECK_FALSE(Queue(carried, pp::StagedBegin{static_cast<uint16_t>(blob.size())}).has_value());
  for (size_t at = 0; at < blob.size(); at += pp::kMaxStagedChunk) {
    pp::StagedPart part{};
    part.offset = static_cast<uint16_t>(at);
    part.data_size = static_cast<uint8_t>(std::min<size_t>(pp::kMaxStagedChunk, blob.size() - at));
    std::copy(blob.begin() + static_cast<long>(at),
              blob.begin() + static_cast<long>(at + part.data_size), part.data.begin());
    CHECK_FALSE(Queue(carried, part).has_value());
  }
}

std::optional<uint32_t> Commit(ph::CarriedHostTimeout& carried, size_t size, uint32_t crc) {
  return Queue(carried, pp::StagedCommit{static_cast<uint16_t>(size), crc});
}

uint32_t CrcOf(const std::vector<uint8_t>& blob) { return pp::Crc32(blob.data(), blob.size()); }

}  // namespace

TEST_GROUP(CarriedHostTimeout) {
  ph::CarriedHostTimeout carried;
  std::vector<uint8_t> blob;
  /// A blob of one board record with a 20 ms timeout, staged.
  void StageABoardRecord() {
    pp::ConfigureBoard board{};
    board.host_timeout_us = 20000;
    AppendRecord(blob, board);
    Stage(carried, blob);
  }
};

TEST(CarriedHostTimeout, AConfigureBoardCarriesItsTimeoutAndOtherCommandsNone) {
  pp::ConfigureBoard board{};
  board.host_timeout_us = 30000;
  const auto timeout = Queue(carried, board);
  CHECK(timeout.has_value());
  LONGS_EQUAL(30000, *timeout);
  CHECK_FALSE(Queue(carried, pp::ClearFault{0xFFFFFFFFu}).has_value());
  CHECK_FALSE(carried.Carried(static_cast<uint8_t>(pp::MessageType::kConfigureBoard), nullptr, 0)
                  .has_value());  // a body that does not decode
}

TEST(CarriedHostTimeout, TheBlobsLastBoardRecordAnywhereInItCarriesItsTimeout) {
  for (uint8_t i = 0; i < 4; ++i) {  // line records first: the board record is found past them
    pp::ConfigureLine line{};
    line.line = i;
    AppendRecord(blob, line);
  }
  pp::ConfigureBoard board{};
  board.host_timeout_us = 50000;
  AppendRecord(blob, board);
  board.host_timeout_us = 20000;  // a second board record: the board applies them in order
  AppendRecord(blob, board);
  CHECK(blob.size() > pp::kMaxStagedChunk);  // more than one part
  Stage(carried, blob);
  const auto timeout = Commit(carried, blob.size(), CrcOf(blob));
  CHECK(timeout.has_value());
  LONGS_EQUAL(20000, *timeout);
}

TEST(CarriedHostTimeout, ABlobWithoutABoardRecordCarriesNone) {
  pp::ConfigureFinger finger{};
  AppendRecord(blob, finger);
  Stage(carried, blob);
  CHECK_FALSE(Commit(carried, blob.size(), CrcOf(blob)).has_value());
}

TEST(CarriedHostTimeout, ACommitThatDoesNotMatchWhatWasStagedCarriesNone) {
  StageABoardRecord();
  CHECK_FALSE(Commit(carried, blob.size(), CrcOf(blob) ^ 1u).has_value());  // the board refuses it
  CHECK_FALSE(Commit(carried, blob.size() + 1, CrcOf(blob)).has_value());
  Queue(carried, pp::StagedBegin{static_cast<uint16_t>(blob.size())});  // begun again, no parts
  CHECK_FALSE(Commit(carried, blob.size(), CrcOf(blob)).has_value());
}

TEST(CarriedHostTimeout, APartPastTheEndChangesNothingAndATruncatedRecordCarriesNone) {
  StageABoardRecord();
  pp::StagedPart beyond{};
  beyond.offset = static_cast<uint16_t>(blob.size());
  beyond.data_size = 4;
  Queue(carried, beyond);  // past the end: nothing written (the board refuses it too)
  const auto timeout = Commit(carried, blob.size(), CrcOf(blob));
  CHECK(timeout.has_value());
  LONGS_EQUAL(20000, *timeout);
  blob.resize(blob.size() - 1);  // the record claims more than the blob holds
  Stage(carried, blob);
  CHECK_FALSE(Commit(carried, blob.size(), CrcOf(blob)).has_value());
}
