// Catalog hash and version refusal: a changed field changes the hash; across a mismatch the host
// completes Hello, refuses every non-bootstrap command naming both versions, and can still flash.
#include <string>

#include "link_harness.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

namespace {

// SetLineSetpoints as a later build might define it: the setpoint range grown to 200 kPa.
struct LineSetpointV2 {
  uint8_t line = 0;
  int32_t setpoint_pa = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("line", m.line, 0, pp::kMaxLines - 1);
    v.Field("setpoint_pa", m.setpoint_pa, -100000, 200000);
  }
};
struct SetLineSetpointsV2 {
  static constexpr pp::MessageInfo kInfo = pp::SetLineSetpoints::kInfo;
  uint32_t generation = 0;
  uint8_t entry_count = 0;
  std::array<LineSetpointV2, pp::kMaxLines> entries{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("generation", m.generation);
    v.Array("entries", m.entries, m.entry_count);
  }
};

// A bootstrap message changed: not covered by the hash (the bootstrap set is frozen instead).
struct EStopWithReason {
  static constexpr pp::MessageInfo kInfo = pp::EStop::kInfo;
  uint8_t reason = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("reason", m.reason);
  }
};

using VariantCatalog = pp::MessageList<pp::Hello, pp::Heartbeat, SetLineSetpointsV2>;
using BaseCatalog = pp::MessageList<pp::Hello, pp::Heartbeat, pp::SetLineSetpoints>;
using BootstrapVariant = pp::MessageList<EStopWithReason, pp::Heartbeat, pp::SetLineSetpoints>;

constexpr uint32_t kVariantHash = pp::ComputeCatalogHash(VariantCatalog{});

}  // namespace

TEST_GROUP(CatalogHash){};

TEST(CatalogHash, OneChangedFieldGivesADifferentHash) {
  CHECK(pp::ComputeCatalogHash(BaseCatalog{}) != kVariantHash);
}

TEST(CatalogHash, BootstrapMessagesDoNotCount) {
  UNSIGNED_LONGS_EQUAL(pp::ComputeCatalogHash(BaseCatalog{}),
                       pp::ComputeCatalogHash(BootstrapVariant{}));
}

TEST(CatalogHash, RenumberedOrAddedFaultOrStatusBitsGiveADifferentHash) {
  // A later build that puts a new fault before output_write: bit 9 means something else.
  constexpr const char* kInserted[] = {
      "host_silence",  "over_limit", "implausible_sensor", "config_crc", "unexpected_reset", "leak",
      "estop_command", "estop_pin",  "pump_run_time",      "overheat",   "output_write"};
  constexpr uint32_t base = pp::ComputeCatalogHash(BaseCatalog{});
  CHECK(base != pp::ComputeCatalogHash(BaseCatalog{}, pp::BitNames{kInserted, 11}));
  CHECK(base != pp::ComputeCatalogHash(BaseCatalog{}, pp::BitNames{kInserted, 9}));  // one fewer
  // Two status bits swapped.
  constexpr const char* kSwapped[] = {"safe",      "trim_clamped", "slewing",      "saturated",
                                      "open_loop", "raw",          "sensor_fault", "shaping"};
  CHECK(base !=
        pp::ComputeCatalogHash(BaseCatalog{}, pp::kFaultBitNames, pp::BitNames{kSwapped, 8}));
  // The same names from another array: the same hash.
  constexpr const char* kSame[] = {"safe",      "slewing", "trim_clamped", "saturated",
                                   "open_loop", "raw",     "sensor_fault", "shaping"};
  UNSIGNED_LONGS_EQUAL(
      base, pp::ComputeCatalogHash(BaseCatalog{}, pp::kFaultBitNames, pp::BitNames{kSame, 8}));
}

TEST(CatalogHash, IsAComputedConstant) {
  UNSIGNED_LONGS_EQUAL(pp::kCatalogHash, pp::ComputeCatalogHash(pp::Catalog{}));
  CHECK(pp::kCatalogHash != pp::ComputeCatalogHash(pp::MessageList<>{}));
}

TEST_GROUP(CatalogMismatch){};

TEST(CatalogMismatch, HelloCompletesThenOnlyTheBootstrapSetIsAllowed) {
  // The board was built from the variant catalog; the host from ours.
  palpa::testing::TestBoard board(kVariantHash, 1024, 5);
  pp::HostSession session;
  session.BeginHello(77);
  std::vector<std::vector<uint8_t>> replies;
  uint8_t frame[pp::kMaxFrameSize];
  auto n = pp::EncodeMessageFrame(pp::Hello{77, 0}, 0, 0, frame, sizeof(frame));
  board.Receive(std::vector<uint8_t>(frame, frame + n.value), replies);
  LONGS_EQUAL(1, replies.size());
  pp::OwningFrameDecoder decoder;
  pp::Status hello_status = pp::Status::kUnavailable;
  for (uint8_t b : replies[0]) {
    if (decoder.Process(b) != pp::FrameDecoder::Event::kFrame) continue;
    pp::DispatchFrame(decoder.frame(), [&](const auto& m, const pp::Header&) {
      if constexpr (std::is_same_v<std::decay_t<decltype(m)>, pp::HelloReply>) {
        hello_status = session.OnHelloReply(m);
      }
    });
  }
  LONGS_EQUAL((int)pp::Status::kCatalogMismatch, (int)hello_status);
  CHECK(session.open());

  int refused = 0, allowed = 0;
  pp::ForEachMessage(pp::Catalog{}, [&]<class M>() {
    if (M::kInfo.sender != pp::Sender::kHost) return;
    const uint8_t type = static_cast<uint8_t>(M::kInfo.type);
    const pp::Status s = session.Admit(type);
    if (pp::IsBootstrap(type)) {
      LONGS_EQUAL_TEXT((int)pp::Status::kOk, (int)s, M::kInfo.name);
      ++allowed;
    } else {
      LONGS_EQUAL_TEXT((int)pp::Status::kCatalogMismatch, (int)s, M::kInfo.name);
      ++refused;
    }
  });
  CHECK(allowed >= 10);  // Hello, EStop and the update set
  CHECK(refused >= 15);

  char text[160];
  session.DescribeVersions(text, sizeof(text));
  const std::string message(text);
  char ours[16], theirs[16];
  snprintf(ours, sizeof(ours), "0x%08x", pp::kCatalogHash);
  snprintf(theirs, sizeof(theirs), "0x%08x", kVariantHash);
  CHECK_TEXT(message.find(ours) != std::string::npos, text);
  CHECK_TEXT(message.find(theirs) != std::string::npos, text);
  CHECK_TEXT(message.find("firmware 0.1.0") != std::string::npos, text);
}

TEST(CatalogMismatch, UpdateMessagesStillWorkAcrossTheMismatch) {
  palpa::testing::ChannelFaults clean;
  palpa::testing::TestBoard board(kVariantHash, 1024, 6);
  palpa::testing::TestHost host(pp::kCatalogHash, 7, 0);
  palpa::testing::LossyChannel to_board(clean, 8), to_host(clean, 9);
  uint64_t now = 0;
  auto step = [&] {
    std::vector<std::vector<uint8_t>> replies;
    board.Receive(to_board.Deliver(now), replies);
    for (const auto& r : replies) to_host.Send(r.data(), r.size(), now);
    host.Step(now, to_host.Deliver(now),
              [&](const uint8_t* f, size_t s) { to_board.Send(f, s, now); });
    now += 250;
  };
  while (!host.session.open()) step();
  CHECK_FALSE(host.session.catalog_matches());
  // The host library checks Admit() before submitting: an update query passes, a setpoint not.
  LONGS_EQUAL((int)pp::Status::kOk, (int)host.session.Admit(0x13));
  LONGS_EQUAL((int)pp::Status::kCatalogMismatch, (int)host.session.Admit(0x21));
  const auto seq = host.sender.Submit(pp::UpdateQuery{1}, 4242);
  CHECK(seq.ok());
  for (int i = 0; i < 100 && host.outcomes.count(4242) == 0; ++i) step();
  LONGS_EQUAL((int)pp::Status::kOk, (int)host.outcomes.at(4242));
}

TEST(CatalogMismatch, NoSessionBeforeHello) {
  pp::HostSession session;
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)session.Admit(0x13));
  LONGS_EQUAL((int)pp::Status::kOk, (int)session.Admit(0x05));
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)pp::BoardAdmit(false, 0x21));
  LONGS_EQUAL((int)pp::Status::kOk, (int)pp::BoardAdmit(false, 0x01));
  LONGS_EQUAL((int)pp::Status::kOk, (int)pp::BoardAdmit(false, 0x05));
  pp::HelloReply stray{};
  stray.host_nonce = 1;
  LONGS_EQUAL((int)pp::Status::kStale, (int)session.OnHelloReply(stray));
}
