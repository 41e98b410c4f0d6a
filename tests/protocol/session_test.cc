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

using Verdict = pp::BoardSession::HelloVerdict;

TEST(BoardSession, RepeatedHelloIsAnsweredWithoutRewindingTheSequence) {
  pp::BoardSession s(1);
  CHECK(s.OnHello(pp::Hello{42, 250}, 0) == Verdict::kOpened);
  const pp::CachedOutcome* cached = nullptr;
  CHECK(s.receiver().Classify(250, &cached) == pp::ReliableReceiver::Verdict::kApply);
  s.receiver().Complete(0x3A, pp::Status::kOk, 0, false);
  CHECK(s.setpoints().Accept(7));
  CHECK(s.OnHello(pp::Hello{42, 250}, 0) == Verdict::kRepeat);  // the same Hello again: no reset
  LONGS_EQUAL(251, s.receiver().expected());
  LONGS_EQUAL(7, s.setpoints().applied());
  s.End();  // closed: a new host session, and everything restarts
  CHECK(s.OnHello(pp::Hello{43, 9}, 0) == Verdict::kOpened);
  LONGS_EQUAL(9, s.receiver().expected());
  CHECK_FALSE(s.setpoints().has_applied());
  CHECK(s.receiver().Classify(250, &cached) == pp::ReliableReceiver::Verdict::kIgnore);
}

TEST(BoardSession, AnotherHostsHelloIsBusyWhileTheSessionIsOpen) {
  pp::BoardSession s(1);
  CHECK(s.OnHello(pp::Hello{42, 0}, 0) == Verdict::kOpened);
  CHECK(s.OnHello(pp::Hello{43, 7}, 0) == Verdict::kBusy);
  CHECK(s.Owns(42));
  CHECK_FALSE(s.Owns(43));
  LONGS_EQUAL(0, s.receiver().expected());  // nothing of the open session changed
  s.End();
  CHECK_FALSE(s.Owns(42));
  CHECK(s.OnHello(pp::Hello{43, 7}, 0) == Verdict::kOpened);
  CHECK(s.Owns(43));
}

TEST(BoardSession, ANonceReusedOnceItsHostWasHeardIsAnotherHost) {
  // Until the host is heard in the session its Hello may be a retry (the reply lost); after
  // that, a Hello with the same nonce is a second host reusing it and inherits nothing.
  pp::BoardSession s(1);
  CHECK(s.OnHello(pp::Hello{42, 0}, 0) == Verdict::kOpened);
  CHECK(s.OnHello(pp::Hello{42, 0}, 0) == Verdict::kRepeat);
  s.Heard(0);
  CHECK(s.OnHello(pp::Hello{42, 0}, 0) == Verdict::kBusy);
  CHECK(s.open());
}

TEST(BoardSession, TheSilenceTimerCountsFromTheHostsLastFreshFrame) {
  // An answered Hello (opened or retried) and a fresh frame restart it; another host's refused
  // Hello does not, and the time stays readable after the session ends.
  pp::BoardSession s(1);
  CHECK(s.OnHello(pp::Hello{42, 0}, 1000) == Verdict::kOpened);
  LONGS_EQUAL(1000, s.last_frame_us());
  CHECK(s.OnHello(pp::Hello{42, 0}, 2000) == Verdict::kRepeat);
  LONGS_EQUAL(2000, s.last_frame_us());
  s.Heard(3000);
  LONGS_EQUAL(3000, s.last_frame_us());
  CHECK(s.OnHello(pp::Hello{43, 0}, 4000) == Verdict::kBusy);
  CHECK(s.OnHello(pp::Hello{42, 0}, 5000) == Verdict::kBusy);
  LONGS_EQUAL(3000, s.last_frame_us());
  s.End();
  LONGS_EQUAL(3000, s.last_frame_us());
  CHECK(s.OnHello(pp::Hello{43, 0}, 6000) == Verdict::kOpened);
  LONGS_EQUAL(6000, s.last_frame_us());
}

TEST(BoardSession, GapIsSignalledOncePerExpectedSeq) {
  pp::BoardSession s(1);
  s.OnHello(pp::Hello{1, 0}, 0);
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

TEST(HostSession, NoticesAnotherHostsReplyFromItsBoard) {
  pp::HostSession h;
  h.BeginHello(9);
  pp::HelloReply r{};
  r.host_nonce = 9;
  r.boot_nonce = 5;
  r.catalog_hash = pp::kCatalogHash;
  CHECK_FALSE(h.TakenOverBy(r));  // no session yet
  LONGS_EQUAL((int)pp::Status::kOk, (int)h.OnHelloReply(r));
  LONGS_EQUAL(9, h.session_tag());
  CHECK_FALSE(h.TakenOverBy(r));  // our own reply again
  r.host_nonce = 10;
  CHECK(h.TakenOverBy(r));  // the board gave another host a session
  r.boot_nonce = 6;
  CHECK_FALSE(h.TakenOverBy(r));  // another board's reply (or a reset: noticed by the nonce)
}
