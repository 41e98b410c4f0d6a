// Board and host session rules: admission before Hello, repeated Hello, boot-nonce change.
#include "palpa/protocol/session.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

TEST_GROUP(BoardSession){};

TEST(BoardSession, OnlyHelloAndEStopBeforeASession) {
  pp::BoardSession s(0xB007);
  CHECK_FALSE(s.open());
  pp::ForEachMessage(pp::Catalog{}, [&]<class M>() {
    if (M::kInfo.sender != pp::Sender::kHost) return;
    const bool allowed =
        M::kInfo.type == pp::MessageType::kHello || M::kInfo.type == pp::MessageType::kEStop;
    LONGS_EQUAL_TEXT((int)(allowed ? pp::Status::kOk : pp::Status::kNoSession),
                     (int)s.Admit(static_cast<uint8_t>(M::kInfo.type)), M::kInfo.name);
  });
}

TEST(BoardSession, RepeatedHelloIsAnsweredWithoutRewindingTheSequence) {
  pp::BoardSession s(1);
  CHECK(s.OnHello(pp::Hello{42, 250}));
  const pp::CachedOutcome* cached = nullptr;
  CHECK(s.receiver().Classify(250, &cached) == pp::ReliableReceiver::Verdict::kApply);
  s.receiver().Complete(0x3A, pp::Status::kOk, 0, false);
  CHECK(s.setpoints().Accept(7));
  CHECK_FALSE(s.OnHello(pp::Hello{42, 250}));  // the same Hello again: no reset
  LONGS_EQUAL(251, s.receiver().expected());
  LONGS_EQUAL(7, s.setpoints().applied());
  CHECK(s.OnHello(pp::Hello{43, 9}));  // a new host session: everything restarts
  LONGS_EQUAL(9, s.receiver().expected());
  CHECK_FALSE(s.setpoints().has_applied());
  CHECK(s.receiver().Classify(250, &cached) == pp::ReliableReceiver::Verdict::kIgnore);
}

TEST(BoardSession, GapIsSignalledOncePerExpectedSeq) {
  pp::BoardSession s(1);
  s.OnHello(pp::Hello{1, 0});
  const pp::CachedOutcome* cached = nullptr;
  CHECK(s.receiver().Classify(3, &cached) == pp::ReliableReceiver::Verdict::kGap);
  CHECK(s.receiver().Classify(4, &cached) == pp::ReliableReceiver::Verdict::kIgnore);
  s.receiver().Complete(0x3A, pp::Status::kOk, 0, false);
  CHECK(s.receiver().Classify(3, &cached) == pp::ReliableReceiver::Verdict::kGap);
  CHECK(s.receiver().Classify(0, &cached) == pp::ReliableReceiver::Verdict::kDuplicate);
  LONGS_EQUAL(0x3A, cached->type);
  CHECK(s.receiver().Classify(100, &cached) == pp::ReliableReceiver::Verdict::kIgnore);
}

TEST_GROUP(HostSession){};

TEST(HostSession, NoticesABoardResetFromTheBootNonce) {
  pp::HostSession h;
  LONGS_EQUAL((int)pp::HostSession::BootCheck::kNoSession, (int)h.CheckBootNonce(5));
  h.BeginHello(9);
  pp::HelloReply r{};
  r.host_nonce = 9;
  r.boot_nonce = 5;
  r.catalog_hash = pp::kCatalogHash;
  LONGS_EQUAL((int)pp::Status::kOk, (int)h.OnHelloReply(r));
  LONGS_EQUAL((int)pp::HostSession::BootCheck::kSame, (int)h.CheckBootNonce(5));
  LONGS_EQUAL((int)pp::HostSession::BootCheck::kReset, (int)h.CheckBootNonce(6));
  LONGS_EQUAL((int)pp::Status::kOk, (int)h.Admit(0x21));
  LONGS_EQUAL((int)pp::Status::kStale, (int)h.OnHelloReply(r));  // answered once only
}
