// The link's sessions: closed on purpose (and on destruction), Close repeated until heard (a
// bootloader's unsupported counts) and falling back to silence, a second host told busy, another
// host's HelloReply noticed, the board ending a silent session, Release keeping the session with
// nothing actuated and nothing resent.
#include <atomic>
#include <chrono>
#include <thread>

#include "board_transport.h"
#include "mini_client.h"
#include "palpa/host/device.h"
#include "palpa/host/link.h"
#include "palpa/protocol/faults.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::testing::BoardTransport;
using palpa::testing::TestBoard;

namespace {

/// Passes everything through until muted; then what the host writes is lost (a cable cut one
/// way, a host frozen mid-write), while what the board sends still arrives.
class MutableTransport final : public ph::Transport {
 public:
  explicit MutableTransport(std::unique_ptr<ph::Transport> inner) : inner_(std::move(inner)) {}
  pp::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    return inner_->Read(out, capacity, timeout_ms);
  }
  ph::Status Write(const uint8_t* data, size_t size) override {
    return muted ? ph::Status::kOk : inner_->Write(data, size);
  }
  std::string Describe() const override { return inner_->Describe(); }
  std::atomic<bool> muted{false};

 private:
  std::unique_ptr<ph::Transport> inner_;
};

std::unique_ptr<ph::Transport> Tcp(const std::string& address) {
  auto t = ph::OpenTransport(address);
  CHECK_TEXT(t.ok(), t.message.c_str());
  return std::move(t.value);
}

std::unique_ptr<ph::Device> OpenDevice(const std::string& address) {
  auto d = ph::Device::Open(address, {});
  CHECK_TEXT(d.ok(), d.message.c_str());
  return std::move(d.value);
}

/// The last telemetry frame `d` receives within `ms`.
pp::Telemetry LastTelemetry(ph::Device& d, int ms) {
  std::mutex mutex;
  pp::Telemetry last{};
  const int id = d.Subscribe([&](const ph::TelemetryFrame& f) {
    std::lock_guard<std::mutex> lock(mutex);
    last = f.telemetry;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  d.Unsubscribe(id);
  return last;
}

bool LineSafe(const pp::Telemetry& t, uint8_t line) {
  return t.tick_count > 0 &&
         (t.samples[(t.tick_count - 1) * t.line_count + line].status & pp::line_status::kSafe) != 0;
}

template <class F>
bool Within(int ms, F&& condition) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

}  // namespace

TEST_GROUP(LinkSession){};

TEST(LinkSession, DestroyingTheLinkClosesTheSessionAndTheNextHostOpensAtOnce) {
  TestBoard board(pp::kCatalogHash, 1024, 21);
  {
    auto link = ph::Link::Open(std::make_unique<BoardTransport>(board), {});
    CHECK_TEXT(link.ok(), link.message.c_str());
  }
  LONGS_EQUAL(1, board.closes);
  auto next = ph::Link::Open(std::make_unique<BoardTransport>(board), {});
  CHECK_TEXT(next.ok(), next.message.c_str());
  LONGS_EQUAL(2, board.sessions);
  LONGS_EQUAL((int)pp::Status::kOk, (int)next.value->Close());
  LONGS_EQUAL((int)pp::Status::kOk, (int)next.value->Close());  // once is enough
  LONGS_EQUAL(2, board.closes);
  const ph::CommandResult after = next.value->Command(pp::ClearFault{1});
  LONGS_EQUAL((int)pp::Status::kNoSession, (int)after.status);
  CHECK_TEXT(after.message.find("closed by this host") != std::string::npos, after.message.c_str());
}

TEST(LinkSession, AnUnansweredCloseIsRepeatedThenLeftToTheBoardsTimeout) {
  TestBoard board(pp::kCatalogHash, 1024, 22);
  auto* transport = new MutableTransport(std::make_unique<BoardTransport>(board));
  ph::LinkOptions options;
  options.close_attempts = 5;
  auto link = ph::Link::Open(std::unique_ptr<ph::Transport>(transport), options);
  CHECK_TEXT(link.ok(), link.message.c_str());
  transport->muted = true;
  const auto start = std::chrono::steady_clock::now();
  LONGS_EQUAL((int)pp::Status::kTimeout, (int)link.value->Close());
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK_TEXT(took >= 5 * 0.020 && took < 2.0, std::to_string(took).c_str());
  LONGS_EQUAL(0, board.closes);
  CHECK(link.value->session_end().find("host-silence timeout") != std::string::npos);
}

TEST(LinkSession, ABootloadersUnsupportedAnswersCloseAndRelease) {
  TestBoard board(pp::kCatalogHash, 1024, 24);
  board.recovery = true;  // no session to end, every line safe: the answer is all that is needed
  ph::LinkOptions options;
  options.close_resend_ms = 200;  // an unheard answer would cost seconds
  auto link = ph::Link::Open(std::make_unique<BoardTransport>(board), options);
  CHECK_TEXT(link.ok(), link.message.c_str());
  const auto start = std::chrono::steady_clock::now();
  LONGS_EQUAL((int)pp::Status::kOk, (int)link.value->Release());
  LONGS_EQUAL((int)pp::Status::kOk, (int)link.value->Close());
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK_TEXT(took < 1.0, std::to_string(took).c_str());
  CHECK_EQUAL("closed by this host", link.value->session_end());
}

TEST(LinkSession, AReleaseStopsResendingWhatWasStreamed) {
  TestBoard board(pp::kCatalogHash, 1024, 25);  // shows nothing applied: streams are resent
  auto link = ph::Link::Open(std::make_unique<BoardTransport>(board), {});
  CHECK_TEXT(link.ok(), link.message.c_str());
  pp::SetLineSetpoints m{};
  m.entry_count = 1;
  m.entries[0] = {0, 30000};
  link.value->StreamSetpoints(m);
  CHECK(Within(1000, [&] { return board.stream_frames >= 3; }));  // resent every 50 ms
  LONGS_EQUAL((int)pp::Status::kOk, (int)link.value->Release());
  const uint32_t after_release = board.stream_frames;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  LONGS_EQUAL(after_release, board.stream_frames);
}

TEST(LinkSession, AReleaseIsSentOnceWhenTheBoardAcksIt) {
  TestBoard board(pp::kCatalogHash, 1024, 26);
  auto link = ph::Link::Open(std::make_unique<BoardTransport>(board), {});
  CHECK_TEXT(link.ok(), link.message.c_str());
  LONGS_EQUAL((int)pp::Status::kOk, (int)link.value->Release());
  // Its Ack ends the wait: an unheard Ack repeats the Release until the board falls silent, which
  // a board answering each one never does (seconds of Releases). A slow machine may resend once.
  CHECK_TEXT(board.releases <= 2, std::to_string(board.releases.load()).c_str());
}

TEST(LinkSession, NoCloseIsSentToABoardWithAnotherCatalog) {
  TestBoard board(0x12345678, 1024, 23);
  auto link = ph::Link::Open(std::make_unique<BoardTransport>(board), {});
  CHECK_TEXT(link.ok(), link.message.c_str());
  LONGS_EQUAL((int)pp::Status::kCatalogMismatch, (int)link.value->Close());
  LONGS_EQUAL(0, board.closes);
}

TEST_GROUP(LinkSessionSim) {
  palpa::testing::SimProcess sim;
  void setup() override {
    CHECK(sim.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0"}));
  }
  void teardown() override { sim.Stop(); }
};

TEST(LinkSessionSim, ASecondHostIsToldBusyAndGetsTheBoardOnceTheFirstCloses) {
  auto first = OpenDevice(sim.address());
  CHECK(first->SetLines({{0, 30.0}}).ok());
  const auto start = std::chrono::steady_clock::now();
  auto second = ph::Device::Open(sim.address(), {});
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  LONGS_EQUAL((int)pp::Status::kBusy, (int)second.status);
  CHECK_TEXT(second.message.find("busy: another host holds the board") != std::string::npos,
             second.message.c_str());
  CHECK_TEXT(took < 1.5, std::to_string(took).c_str());  // not the 3 s of an unanswered Hello
  // The first host was not disturbed.
  CHECK_FALSE(LineSafe(LastTelemetry(*first, 100), 0));
  CHECK(first->Close().ok());
  auto third = OpenDevice(sim.address());  // at once: no waiting for a timeout
  const pp::Telemetry t = LastTelemetry(*third, 100);
  CHECK(LineSafe(t, 0));
  LONGS_EQUAL(0, t.fault_bitmap);  // a Close is no fault
}

TEST(LinkSessionSim, AHostThatSeesAnotherHostsHelloReplyKnowsItLostTheBoard) {
  auto* transport = new MutableTransport(Tcp(sim.address()));
  auto link = ph::Link::Open(std::unique_ptr<ph::Transport>(transport), {});
  CHECK_TEXT(link.ok(), link.message.c_str());
  transport->muted = true;  // this host goes quiet: the board ends its session (nothing actuated)
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  palpa::testing::MiniClient other;
  const std::string& a = sim.address();
  CHECK(other.ConnectTcp("127.0.0.1", std::atoi(a.c_str() + a.rfind(':') + 1)));
  CHECK(other.Hello(0xA11CE).ok());
  CHECK(Within(1000, [&] { return !link.value->session_open(); }));
  CHECK_TEXT(link.value->session_end().find("another host") != std::string::npos,
             link.value->session_end().c_str());
  // It stays off the board: no reconnection, no heartbeats.
  const uint64_t heartbeats = link.value->counters().heartbeats;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  LONGS_EQUAL(heartbeats, link.value->counters().heartbeats);
  CHECK_FALSE(link.value->session_open());
  bool told = false;
  for (const std::string& e : link.value->TakeEvents()) told |= e.find("another host") == 0;
  CHECK(told);
}

TEST(LinkSessionSim, AHostTheBoardTimedOutIsToldSoAndOpensANewSession) {
  auto* transport = new MutableTransport(Tcp(sim.address()));
  ph::DeviceOptions options;
  auto device = ph::Device::Attach(std::unique_ptr<ph::Transport>(transport), options);
  CHECK_TEXT(device.ok(), device.message.c_str());
  ph::Device& d = *device.value;
  CHECK(d.SetLines({{0, 30.0}}).ok());
  transport->muted = true;  // the host stalls for longer than the board's timeout
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  transport->muted = false;
  std::string events;  // its next frame is answered no_session
  CHECK(Within(1000, [&] {
    for (const std::string& e : d.link().TakeEvents()) events += e + "; ";
    return !events.empty();
  }));
  CHECK_TEXT(events.find("the board ended the session") == 0, events.c_str());
  CHECK(Within(1000, [&] { return d.link().session_open(); }));
  // It left the board actuated: that is a fault, which the new session sees and must clear.
  LONGS_EQUAL(pp::FaultBit(pp::Fault::kHostSilence), d.info().fault_bitmap);
}

TEST(LinkSessionSim, AfterAReleaseNothingActuatesUntilTheHostSaysSo) {
  auto d = OpenDevice(sim.address());
  CHECK(d->SetLines({{0, 30.0}}).ok());
  CHECK_FALSE(LineSafe(LastTelemetry(*d, 100), 0));
  const ph::Outcome released = d->Release();
  CHECK_TEXT(released.ok(), released.message.c_str());
  const pp::Telemetry t = LastTelemetry(*d, 300);  // six stream resend periods
  CHECK(LineSafe(t, 0));
  LONGS_EQUAL(0, t.fault_bitmap);
  CHECK(d->link().session_open());
  CHECK(d->SetLines({{0, 20.0}}).ok());  // the session goes on
  CHECK_FALSE(LineSafe(LastTelemetry(*d, 100), 0));
}
