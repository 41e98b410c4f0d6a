// The link against a test board behind a fault-injecting transport: exactly-once commands under
// loss and corruption, board restarts, an unplugged cable, a refused stream, heartbeats, catalog
// mismatch, fault names.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "board_transport.h"
#include "palpa/host/bit_names.h"
#include "palpa/host/fault_text.h"
#include "palpa/host/fault_transport.h"
#include "palpa/host/link.h"
#include "palpa/protocol/faults.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::testing::BoardTransport;
using palpa::testing::TestBoard;

namespace {

std::unique_ptr<ph::Link> OpenLink(std::unique_ptr<ph::Transport> t, ph::LinkOptions options = {}) {
  auto link = ph::Link::Open(std::move(t), options);
  CHECK_TEXT(link.ok(), link.message.c_str());
  return std::move(link.value);
}

}  // namespace

TEST_GROUP(LinkFaults){};

TEST(LinkFaults, ThousandCommandsExactlyOnceInOrderAtOnePercentLossAndBitFlips) {
  TestBoard board(pp::kCatalogHash, 1024, 11);
  ph::FaultSpec faults;
  faults.drop = 0.01;
  faults.bit_flip = 0.001;
  // At these rates about a third of all round trips fail (a 14-byte command and a 15-byte Ack),
  // so now and then a command needs eight or more transmissions, half a second apart once the
  // back-off is at its cap. This test is about exactly-once delivery, not latency: give each
  // command 30 s instead of the default 3 s.
  ph::LinkOptions patient;
  patient.command_timeout_ms = 30000;
  auto link = OpenLink(
      std::make_unique<ph::FaultTransport>(std::make_unique<BoardTransport>(board), faults, 5),
      patient);
  for (uint32_t id = 1; id <= 1000; ++id) {
    const ph::CommandResult r = link->Command(pp::ClearFault{id});
    LONGS_EQUAL_TEXT((int)pp::Status::kOk, (int)r.status,
                     (std::to_string(id) + " " + r.message).c_str());
  }
  LONGS_EQUAL(1000, board.applied.size());
  for (uint32_t i = 0; i < 1000; ++i) LONGS_EQUAL(i + 1, board.applied[i].command_id);
  CHECK(link->counters().retransmissions > 0);
  LONGS_EQUAL(1, board.sessions);
}

TEST(LinkFaults, BoardRestartReportsInFlightCommandsAsOutcomeUnknownAndReconnects) {
  TestBoard board(pp::kCatalogHash, 1024, 12);
  ph::FaultSpec slow;
  slow.delay_ms = 30;  // commands stay in flight long enough to be caught by the reset
  auto* transport = new BoardTransport(board);
  auto link = OpenLink(
      std::make_unique<ph::FaultTransport>(std::unique_ptr<ph::Transport>(transport), slow, 6));
  std::atomic<int> unknown{0}, ok{0};
  std::thread sender([&] {
    for (uint32_t id = 1; id <= 40; ++id) {
      const ph::CommandResult r = link->Command(pp::ClearFault{id});
      if (r.status == pp::Status::kOutcomeUnknown) ++unknown;
      if (r.status == pp::Status::kOk) ++ok;
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  transport->Reboot();
  sender.join();
  CHECK(unknown.load() >= 1);
  CHECK(ok.load() >= 1);
  CHECK(link->counters().board_resets >= 1);
  bool told = false;
  for (const std::string& e : link->TakeEvents())
    told |= e.find("unknown outcome") != std::string::npos;
  CHECK(told);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)link->Command(pp::ClearFault{999}).status);  // a new session works
  CHECK(board.sessions >= 2);
}

namespace {

/// A cable to a test board that can be pulled: while it is out the transport reports the device
/// gone, and opening it again fails until it is back in.
struct Cable {
  std::atomic<bool> plugged{true};
  std::atomic<int> opened{0};
  std::mutex mutex;
  std::vector<uint8_t> injected;  ///< bytes the host reads before the board's (another host's)
};

class PluggedTransport final : public ph::Transport {
 public:
  PluggedTransport(TestBoard& board, Cable& cable) : board_(board), cable_(cable) {
    ++cable_.opened;
  }
  pp::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    if (!cable_.plugged) return pp::Status::kDisconnected;
    {
      std::lock_guard<std::mutex> lock(cable_.mutex);
      if (!cable_.injected.empty()) {
        const size_t n = std::min(capacity, cable_.injected.size());
        std::copy(cable_.injected.begin(), cable_.injected.begin() + n, out);
        cable_.injected.erase(cable_.injected.begin(), cable_.injected.begin() + n);
        return n;
      }
    }
    return board_.Read(out, capacity, timeout_ms);
  }
  ph::Status Write(const uint8_t* data, size_t size) override {
    return cable_.plugged ? board_.Write(data, size) : pp::Status::kDisconnected;
  }
  std::string Describe() const override { return "usb:test"; }

 private:
  BoardTransport board_;
  Cable& cable_;
};

/// Link options that reopen a PluggedTransport on `cable` whenever it is plugged in.
ph::LinkOptions ReopeningOptions(TestBoard& board, Cable& cable) {
  ph::LinkOptions options;
  options.command_timeout_ms = 300;
  options.reopen_interval_ms = 20;
  options.reopen = [&]() -> ph::Result<std::unique_ptr<ph::Transport>> {
    if (!cable.plugged) return {pp::Status::kNotFound, "no such device"};
    return std::unique_ptr<ph::Transport>(new PluggedTransport(board, cable));
  };
  return options;
}

/// Pulls the cable, waits well past a few reopen intervals while the board's host-silence timeout
/// ends whatever session it held (a Hello would open a new one), plugs it back in and waits again.
void UnplugAndReplug(TestBoard& board, Cable& cable) {
  cable.plugged = false;
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  board.SilenceEndsTheSession();  // nothing reaches the board while the cable is out
  cable.plugged = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
}

}  // namespace

TEST(LinkFaults, AnUnpluggedBoardIsReportedAndReopenedWithANewSessionWhenItIsBack) {
  TestBoard board(pp::kCatalogHash, 1024, 16);
  Cable cable;
  auto link =
      OpenLink(std::make_unique<PluggedTransport>(board, cable), ReopeningOptions(board, cable));
  LONGS_EQUAL((int)pp::Status::kOk, (int)link->Command(pp::ClearFault{1}).status);

  cable.plugged = false;
  for (int i = 0; i < 100 && link->session_open(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK(!link->session_open());
  const ph::CommandResult unplugged = link->Command(pp::ClearFault{2});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)unplugged.status);
  LONGS_EQUAL(1, link->counters().transport_lost);
  LONGS_EQUAL(1, cable.opened.load());  // nothing opened while the cable is out
  CHECK(!link->ended());                // a monitor waits for the board to come back

  board.SilenceEndsTheSession();  // the silent host's session ends, as on a board left powered
  cable.plugged = true;
  for (int i = 0; i < 200 && !link->session_open(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK(link->session_open());
  LONGS_EQUAL((int)pp::Status::kOk, (int)link->Command(pp::ClearFault{3}).status);
  LONGS_EQUAL(1, link->counters().reopens);
  LONGS_EQUAL(2, board.sessions);
  std::string events;
  for (const std::string& e : link->TakeEvents()) events += e + "\n";
  CHECK_TEXT(events.find("the link to usb:test was lost") != std::string::npos, events.c_str());
  CHECK_TEXT(events.find("reopened usb:test") != std::string::npos, events.c_str());
}

TEST(LinkFaults, ABoardThisHostClosedIsNotReopenedWhenItIsUnpluggedAndBack) {
  TestBoard board(pp::kCatalogHash, 1024, 18);
  Cable cable;
  auto link =
      OpenLink(std::make_unique<PluggedTransport>(board, cable), ReopeningOptions(board, cable));
  LONGS_EQUAL((int)pp::Status::kOk, (int)link->Close());
  UnplugAndReplug(board, cable);
  LONGS_EQUAL(1, cable.opened.load());
  LONGS_EQUAL(0, link->counters().reopens);
  LONGS_EQUAL(1, board.sessions);
  CHECK(!link->session_open());
}

TEST(LinkFaults, ABoardAnotherHostHoldsIsNotReopenedWhenItIsUnpluggedAndBack) {
  TestBoard board(pp::kCatalogHash, 1024, 19);
  Cable cable;
  auto link =
      OpenLink(std::make_unique<PluggedTransport>(board, cable), ReopeningOptions(board, cable));
  // Another host's session, as the board announces it on a shared link.
  pp::HelloReply other{};
  other.host_nonce = 0x5eca11ed;
  other.boot_nonce = board.boot_nonce();
  other.rx_buffer_bytes = 1024;
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(other, 0, pp::flags::kFromBoard, frame, sizeof(frame));
  CHECK(n.ok());
  {
    std::lock_guard<std::mutex> lock(cable.mutex);
    cable.injected.assign(frame, frame + n.value);
  }
  for (int i = 0; i < 100 && !link->ended(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  CHECK(link->ended());
  UnplugAndReplug(board, cable);
  LONGS_EQUAL(1, cable.opened.load());
  LONGS_EQUAL(0, link->counters().reopens);
  LONGS_EQUAL(1, board.sessions);
}

TEST(LinkFaults, WithoutAWayToReopenALostTransportEndsTheLink) {
  TestBoard board(pp::kCatalogHash, 1024, 17);
  Cable cable;
  auto link = OpenLink(std::make_unique<PluggedTransport>(board, cable));
  cable.plugged = false;
  for (int i = 0; i < 100 && link->session_open(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)link->Command(pp::ClearFault{1}).status);
  bool closed = false;
  for (const std::string& e : link->TakeEvents()) closed |= e == "the link to usb:test closed";
  CHECK(closed);
  cable.plugged = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(!link->session_open());
  LONGS_EQUAL(1, cable.opened.load());
}

TEST(LinkFaults, AStreamedValueTheBoardRefusesIsReportedAtOnceAndNotResent) {
  TestBoard board(pp::kCatalogHash, 1024, 15);
  auto link = OpenLink(std::make_unique<BoardTransport>(board));
  pp::SetLineSetpoints m{};
  m.entry_count = 2;
  m.entries[0] = {0, 30000};
  m.entries[1] = {TestBoard::kLines, 30000};  // a line the board does not have
  const uint32_t generation = link->StreamSetpoints(m);
  uint32_t detail = 99;
  // The refusal answers the wait: unrecorded, the wait runs out as if nothing had been heard.
  LONGS_EQUAL((int)pp::Status::kNotFound,
              (int)link->WaitSetpointsApplied(generation, 2000, &detail));
  LONGS_EQUAL(1, detail);  // the entry naming the missing line
  // A refused value is not resent every stream_resend_ms (50) to be refused again.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  LONGS_EQUAL(1, board.stream_frames);
}

TEST(LinkFaults, ABoardThatReportsNoHostTimeoutGetsHeartbeatsAtTheDefaultRate) {
  TestBoard board(pp::kCatalogHash, 1024, 14);  // its HelloReply leaves host_timeout_us at 0
  const double start = ph::SteadySeconds();
  auto link = OpenLink(std::make_unique<BoardTransport>(board));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const uint64_t heartbeats = link->counters().heartbeats;
  const double elapsed = ph::SteadySeconds() - start;
  // A quarter of the default 100 ms: at most one per 25 ms (a slow machine only sends fewer).
  // Read as "as fast as possible", 0 made the link send one every millisecond.
  CHECK(heartbeats >= 1);
  CHECK_TEXT(
      heartbeats <= elapsed / 0.025 + 2,
      (std::to_string(heartbeats) + " heartbeats in " + std::to_string(elapsed) + " s").c_str());
}

TEST(LinkFaults, CatalogMismatchRefusesEverythingButTheBootstrapSet) {
  TestBoard board(0x12345678, 1024, 13);
  auto link = OpenLink(std::make_unique<BoardTransport>(board));
  CHECK_FALSE(link->catalog_matches());
  const ph::CommandResult refused = link->Command(pp::ClearFault{1});
  LONGS_EQUAL((int)pp::Status::kCatalogMismatch, (int)refused.status);
  CHECK(refused.message.find("0x12345678") != std::string::npos);
  CHECK(refused.message.find("host catalog") != std::string::npos);
  const ph::CommandResult update = link->Command(pp::UpdateQuery{1});
  LONGS_EQUAL((int)pp::Status::kOk, (int)update.status);
  pp::UpdateStatus st{};
  CHECK(update.Reply(st));
  LONGS_EQUAL(1234, st.written_bytes);
  CHECK(board.applied.empty());
}

TEST(LinkFaults, FaultNamesShowEveryFaultIncludingOnesThisHostDoesNotKnow) {
  STRCMP_EQUAL("none", ph::FaultNames(0).c_str());
  const uint32_t known =
      pp::FaultBit(pp::Fault::kHostSilence) | pp::FaultBit(pp::Fault::kOutputWrite);
  STRCMP_EQUAL("host_silence, output_write", ph::FaultNames(known).c_str());
  STRCMP_EQUAL("leak, fault_31",
               ph::FaultNames(pp::FaultBit(pp::Fault::kLeak) | (1u << 31)).c_str());
  // The fault history names its entries the same way (a history entry carries the bit index).
  STRCMP_EQUAL("output_write",
               ph::FaultName(static_cast<uint8_t>(pp::Fault::kOutputWrite)).c_str());
  STRCMP_EQUAL("fault_10", ph::FaultName(static_cast<uint8_t>(pp::Fault::kCount)).c_str());
}

TEST(LinkFaults, AnOutputWriteDetailNamesTheOutput) {
  using pp::OutputKind;
  using pp::OutputWriteDetail;
  const auto f = static_cast<uint8_t>(pp::Fault::kOutputWrite);
  STRCMP_EQUAL("line 3's DAC channel",
               ph::FaultDetail(f, OutputWriteDetail(OutputKind::kDac, 2), 1).c_str());
  STRCMP_EQUAL("line 0's valve",
               ph::FaultDetail(f, OutputWriteDetail(OutputKind::kLineValve, 0), 0).c_str());
  STRCMP_EQUAL("supply enable",
               ph::FaultDetail(f, OutputWriteDetail(OutputKind::kSupplyEnable), 1).c_str());
  STRCMP_EQUAL("pump enable",
               ph::FaultDetail(f, OutputWriteDetail(OutputKind::kPumpEnable), 1).c_str());
  STRCMP_EQUAL("", ph::FaultDetail(f, 0x7FF, 1).c_str());  // a kind a newer board may send
}
