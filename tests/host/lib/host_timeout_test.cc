// The host-silence timeout the host follows through a session, and the heartbeat period from it.
#include "palpa/host/host_timeout.h"

#include <algorithm>
#include <vector>

#include "palpa/protocol/codec.h"
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

/// A staged blob's records as the board reads them: 16-bit length, type, body.
template <class M>
void AppendRecord(std::vector<uint8_t>& blob, const M& message) {
  uint8_t body[512];
  const auto size = pp::EncodeBody(message, body, sizeof(body));
  CHECK(size.ok());
  blob.push_back(static_cast<uint8_t>(size.value));
  blob.push_back(static_cast<uint8_t>(size.value >> 8));
  blob.push_back(static_cast<uint8_t>(M::kInfo.type));
  blob.insert(blob.end(), body, body + size.value);
}

/// Stages `blob` in chunks, as a host would, and returns what the commit carries.
std::optional<uint32_t> StageAndCommit(ph::StagedHostTimeout& staged,
                                       const std::vector<uint8_t>& blob, uint32_t crc) {
  staged.OnBegin(pp::StagedBegin{static_cast<uint16_t>(blob.size())});
  for (size_t at = 0; at < blob.size(); at += pp::kMaxStagedChunk) {
    pp::StagedPart part{};
    part.offset = static_cast<uint16_t>(at);
    part.data_size = static_cast<uint8_t>(std::min<size_t>(pp::kMaxStagedChunk, blob.size() - at));
    std::copy(blob.begin() + static_cast<long>(at),
              blob.begin() + static_cast<long>(at + part.data_size), part.data.begin());
    staged.OnPart(part);
  }
  return staged.OnCommit(pp::StagedCommit{static_cast<uint16_t>(blob.size()), crc});
}

}  // namespace

TEST_GROUP(StagedHostTimeout) {
  ph::StagedHostTimeout staged;
  std::vector<uint8_t> blob;
};

TEST(StagedHostTimeout, TheBlobsLastBoardRecordAnywhereInItCarriesItsTimeout) {
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
  const auto carried = StageAndCommit(staged, blob, pp::Crc32(blob.data(), blob.size()));
  CHECK(carried.has_value());
  LONGS_EQUAL(20000, *carried);
}

TEST(StagedHostTimeout, ABlobWithoutABoardRecordCarriesNone) {
  pp::ConfigureFinger finger{};
  AppendRecord(blob, finger);
  CHECK_FALSE(StageAndCommit(staged, blob, pp::Crc32(blob.data(), blob.size())).has_value());
}

TEST(StagedHostTimeout, ACommitThatDoesNotMatchWhatWasStagedCarriesNone) {
  pp::ConfigureBoard board{};
  board.host_timeout_us = 20000;
  AppendRecord(blob, board);
  const uint32_t crc = pp::Crc32(blob.data(), blob.size());
  CHECK_FALSE(StageAndCommit(staged, blob, crc ^ 1u).has_value());  // the board refuses it
  staged.OnBegin(pp::StagedBegin{static_cast<uint16_t>(blob.size())});  // begun again, no parts
  const auto size = static_cast<uint16_t>(blob.size());
  CHECK_FALSE(staged.OnCommit(pp::StagedCommit{size, crc}).has_value());
  CHECK_FALSE(staged.OnCommit(pp::StagedCommit{static_cast<uint16_t>(size + 1), crc}).has_value());
}

TEST(StagedHostTimeout, AStrayPartOrATruncatedRecordIsIgnored) {
  pp::ConfigureBoard board{};
  board.host_timeout_us = 20000;
  AppendRecord(blob, board);
  blob.resize(blob.size() - 1);  // the record claims more than the blob holds
  staged.OnBegin(pp::StagedBegin{static_cast<uint16_t>(blob.size())});
  pp::StagedPart beyond{};
  beyond.offset = static_cast<uint16_t>(blob.size());
  beyond.data_size = 4;
  staged.OnPart(beyond);  // past the end: nothing written
  CHECK_FALSE(StageAndCommit(staged, blob, pp::Crc32(blob.data(), blob.size())).has_value());
}
