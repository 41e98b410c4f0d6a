// The link against a test board behind a fault-injecting transport, and against palpa-sim:
// exactly-once commands under loss and corruption, board restarts, streams, slow subscribers,
// catalog mismatch.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "board_transport.h"
#include "config_record.h"
#include "mini_client.h"
#include "palpa/host/device.h"
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

/// Configures the thesis-5finger board with a host-silence timeout of `host_timeout_us`.
void ConfigureHostTimeout(ph::Device& device, uint32_t host_timeout_us) {
  pp::ConfigureBoard board{};
  std::snprintf(board.config_name.data(), board.config_name.size(), "thesis-5finger");
  board.host_timeout_us = host_timeout_us;
  const ph::Outcome configured = device.ConfigureBoard(board);
  CHECK_TEXT(configured.ok(), configured.message.c_str());
}

/// palpa-sim with thesis-5finger running at `speed` times real time (slowed down, a test's
/// timeouts in board time become longer in host time).
std::unique_ptr<ph::Transport> LaunchSimAt(const char* speed) {
  auto sim = ph::LaunchSim("thesis-5finger", {"--speed", speed}, nullptr);
  CHECK_TEXT(sim.ok(), sim.message.c_str());
  return std::move(sim.value);
}

/// A device on palpa-sim at `speed` times real time.
std::unique_ptr<ph::Device> OpenSimAt(const char* speed) {
  auto device = ph::Device::Attach(LaunchSimAt(speed), {});
  CHECK_TEXT(device.ok(), device.message.c_str());
  return std::move(device.value);
}

/// One Configure* record as a staged blob holds it.
template <class M>
std::vector<uint8_t> StagedRecord(const M& message) {
  std::vector<uint8_t> record = palpa::testing::ConfigRecord(message);
  CHECK(!record.empty());
  return record;
}

}  // namespace

/// The board's latched faults in words, for failure messages.
std::string LatchedFaults(ph::Device& device) {
  const auto diagnostics = device.Diagnostics();
  return diagnostics.ok() ? "latched: " + ph::FaultNames(diagnostics.value.fault_bitmap)
                          : "no diagnostics";
}

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

TEST_GROUP(LinkSim){};

TEST(LinkSim, StreamsConvergeToTheLatestValueUnderFaults) {
  // At a quarter of real time: until the 1 s timeout below lands, the session runs on the
  // opening 100 ms one, which a starved machine could otherwise trip (400 ms of host time here).
  ph::FaultSpec faults;
  faults.drop = 0.01;
  faults.bit_flip = 0.001;
  auto device =
      ph::Device::Attach(std::make_unique<ph::FaultTransport>(LaunchSimAt("0.25"), faults, 7), {});
  CHECK_TEXT(device.ok(), device.message.c_str());
  // A 1 % byte loss drops about one heartbeat in seven; four in a row would trip the default
  // 100 ms host-silence timeout now and then. This test is about the stream, so give it 1 s.
  ConfigureHostTimeout(*device.value, 1000000);
  for (int i = 1; i <= 30; ++i) device.value->SetLines({{0, static_cast<double>(i)}}, false);
  const ph::Outcome last = device.value->SetLines({{0, 42.0}}, true);
  CHECK_TEXT(last.ok(), (last.message + " (" + LatchedFaults(*device.value) + ")").c_str());
  std::atomic<int32_t> seen{0};
  const int id = device.value->Subscribe(
      [&](const ph::TelemetryFrame& f) { seen = f.telemetry.samples[0].setpoint_pa; });
  for (int i = 0; i < 250 && seen.load() != 42000; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  device.value->Unsubscribe(id);
  LONGS_EQUAL(42000, seen.load());
}

TEST(LinkSim, AStalledSubscriberStallsNeitherCommandsNorHeartbeats) {
  // At a quarter of real time the board's 100 ms timeout is 400 ms of host time (scheduling
  // margin on a loaded machine), and the second of stall below is still 250 ms of board time:
  // heartbeats that stopped with the subscriber would trip it.
  const auto device = OpenSimAt("0.25");
  std::atomic<bool> blocked{false}, release{false};
  const int id = device->Subscribe([&](const ph::TelemetryFrame&) {
    blocked = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  });
  while (!blocked) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  for (int i = 0; i < 20; ++i) {  // while the callback is stuck
    CHECK(device->LoopStats().ok());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  CHECK(blocked.load());
  const auto diagnostics = device->Diagnostics();
  CHECK(diagnostics.ok());
  LONGS_EQUAL(0, diagnostics.value.fault_bitmap);  // heartbeats kept the board from going safe
  release = true;
  device->Unsubscribe(id);
}

TEST(LinkSim, UnsubscribeReturnsOnlyOnceTheCallbackHasReturned) {
  // What the callback uses may go once Unsubscribe returns: it is not running and never runs
  // again (here it captures this test's locals).
  const auto device = OpenSimAt("1");
  std::atomic<bool> inside{false}, running{false}, unsubscribed{false};
  std::atomic<int> calls_after{0};
  const int id = device->Subscribe([&](const ph::TelemetryFrame&) {
    running = true;
    inside = true;
    if (unsubscribed) ++calls_after;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    running = false;
  });
  while (!inside) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  device->Unsubscribe(id);
  unsubscribed = true;
  CHECK_FALSE(running.load());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // several more frames
  LONGS_EQUAL(0, calls_after.load());
}

TEST(LinkSim, ACallbackMayUnsubscribeItself) {
  const auto device = OpenSimAt("1");
  std::atomic<int> id{0}, calls{0};
  std::atomic<bool> done{false};
  id = device->Subscribe([&](const ph::TelemetryFrame&) {
    while (id.load() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ++calls;
    device->Unsubscribe(id);  // from the dispatcher's own thread: must not wait for itself
    done = true;
  });
  while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  LONGS_EQUAL(1, calls.load());
}

TEST(LinkSim, DeviceConfiguresReadsBackAndRecords) {
  auto opened = ph::Device::Open("sim:thesis-jamming-2", {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  auto board = d.ReadBoard();
  CHECK(board.ok());
  STRCMP_EQUAL("thesis-jamming-2", board.value.config_name.data());
  board.value.host_timeout_us = 150000;
  CHECK(d.ConfigureBoard(board.value).ok());
  LONGS_EQUAL(150000, d.ReadBoard().value.host_timeout_us);
  auto finger = d.ReadFinger(1);
  CHECK(finger.ok());
  LONGS_EQUAL(20000, finger.value.bias_pa);
  // PI(32) is over one packet: it goes staged. An odd count is refused, a whole set applied.
  pp::ConfigureFinger pi = finger.value;
  pi.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  pi.param_count = 65;
  LONGS_EQUAL((int)pp::Status::kBadValue, (int)d.ConfigureFinger(pi).status);
  pi.param_count = 66;
  pi.params[0] = 700;     // mN/mm with the vacuum released
  pi.params[1] = 0.006f;  // mN/mm per Pa
  for (int i = 0; i < 32; ++i) {
    pi.params[2 + i] = 1500.0f * static_cast<float>(i);
    pi.params[34 + i] = 0.0001f;
  }
  CHECK(d.ConfigureFinger(pi).ok());
  LONGS_EQUAL(66, d.ReadFinger(1).value.param_count);
  CHECK(d.Set({{0, {ph::TargetKind::kStiffnessNPerMm, 1.1}}}).ok());
  const std::string path = "/tmp/palpa-record-" + std::to_string(getpid()) + ".csv";
  // A link planted where a recording's temporary might go must not redirect it.
  const std::string victim = path + ".victim";
  std::ofstream(victim) << "precious";
  CHECK(symlink(victim.c_str(), (path + ".part").c_str()) == 0);
  CHECK(d.StartRecording(path).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK(access(path.c_str(), F_OK) != 0);  // not there until complete
  CHECK(d.StopRecording().ok());
  FILE* f = fopen(path.c_str(), "r");
  CHECK(f != nullptr);
  char line[4096];
  CHECK(fgets(line, sizeof(line), f) != nullptr);
  CHECK(std::string(line).find("\"configuration\":\"thesis-jamming-2\"") != std::string::npos);
  CHECK(fgets(line, sizeof(line), f) != nullptr);  // a column per line and per finger
  CHECK(std::string(line).find(",line4_status,finger1_n_per_mm,finger2_n_per_mm") !=
        std::string::npos);
  int rows = 0;
  while (fgets(line, sizeof(line), f) != nullptr) ++rows;
  fclose(f);
  remove(path.c_str());
  CHECK_TEXT(rows > 100, std::to_string(rows).c_str());  // a row per sample: 300 in 300 ms
  std::ifstream kept(victim);
  std::string contents;
  std::getline(kept, contents);
  STRCMP_EQUAL("precious", contents.c_str());
  remove(victim.c_str());
  remove((path + ".part").c_str());
  // The long layout: a row per line per sample.
  CHECK(d.StartRecording(path, ph::RecordLayout::kLong).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CHECK(d.StopRecording().ok());
  f = fopen(path.c_str(), "r");
  CHECK(f != nullptr);
  rows = -2;  // the header and the column names
  while (fgets(line, sizeof(line), f) != nullptr) ++rows;
  fclose(f);
  remove(path.c_str());
  CHECK_TEXT(rows > 4 * 100, std::to_string(rows).c_str());
}

TEST(LinkSim, OverARealPtyWithSerialSettings) {
  const std::string path = "/tmp/palpa-host-serial-" + std::to_string(getpid());
  palpa::testing::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "pty:" + path}));
  auto device = ph::Device::Open("serial:" + path + "?baud=115200", {});
  CHECK_TEXT(device.ok(), device.message.c_str());
  STRCMP_EQUAL("thesis-pneumatic-3", device.value->info().config_name.data());
  const ph::Outcome set = device.value->Set({{2, {ph::TargetKind::kLevel, 1}}});
  CHECK_TEXT(set.ok(), set.message.c_str());
  CHECK(set.notes[0].find("nominal thesis curves") != std::string::npos);
  CHECK(device.value->EStop().ok());
  device.value.reset();
  LONGS_EQUAL(0, sim.Stop());
}

TEST(LinkSim, HeartbeatsFollowAShorterHostTimeoutSetInTheSession) {
  // At a tenth of real time the board's 20 ms timeout is 200 ms of host time: heartbeats at a
  // quarter of it leave 150 ms for scheduling, while the 250 ms period of the session's opening
  // timeout (100 ms) would trip it. The test decides on the period, not on the machine's load.
  const auto device = OpenSimAt("0.1");
  ConfigureHostTimeout(*device, 20000);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto diagnostics = device->Diagnostics();
  CHECK_TEXT(diagnostics.ok(), diagnostics.message.c_str());
  STRCMP_EQUAL("none", ph::FaultNames(diagnostics.value.fault_bitmap).c_str());
}

TEST(LinkSim, HeartbeatsFollowAShorterHostTimeoutInAStagedConfiguration) {
  // As above, with the board record inside a staged blob (palpa config set/load): the link reads
  // the timeout from what it staged when the commit goes out.
  const auto device = OpenSimAt("0.1");
  auto board = device->ReadBoard();
  CHECK_TEXT(board.ok(), board.message.c_str());
  board.value.host_timeout_us = 20000;
  const std::vector<uint8_t> blob = StagedRecord(board.value);
  // Sizes the board's staging buffer cannot hold are refused before anything is sent.
  LONGS_EQUAL(pp::Status::kBadLength, device->ConfigureStaged(blob.data(), 0).status);
  const std::vector<uint8_t> oversized(pp::kMaxStagedBytes + 1u);
  const ph::Outcome refused = device->ConfigureStaged(oversized.data(), oversized.size());
  LONGS_EQUAL(pp::Status::kBadLength, refused.status);
  CHECK(refused.message.find("staging buffer") != std::string::npos);
  const ph::Outcome staged = device->ConfigureStaged(blob.data(), blob.size());
  CHECK_TEXT(staged.ok(), staged.message.c_str());
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto diagnostics = device->Diagnostics();
  CHECK_TEXT(diagnostics.ok(), diagnostics.message.c_str());
  STRCMP_EQUAL("none", ph::FaultNames(diagnostics.value.fault_bitmap).c_str());
}

TEST(LinkSim, AStagedConfigurationTheBoardRefusesNamesTheRecordAndChangesNothing) {
  const auto device = OpenSimAt("1");
  std::string error;
  auto line = device->ReadLine(3);  // a bias line: its ceiling is below 30 kPa
  CHECK_TEXT(line.ok(), error.c_str());
  const int32_t limit_before = line.value.limit_max_pa;
  line.value.limit_max_pa = 30000;
  const std::vector<uint8_t> blob = StagedRecord(line.value);
  const ph::Outcome refused = device->ConfigureStaged(blob.data(), blob.size());
  CHECK_FALSE(refused.ok());
  CHECK_TEXT(refused.message.find("staged commit") != std::string::npos, refused.message.c_str());
  // Named as this API numbers lines (from 0): ReadLine(3) above.
  CHECK_TEXT(refused.message.find("(line 3)") != std::string::npos, refused.message.c_str());
  const auto after = device->ReadLine(3);
  CHECK_TEXT(after.ok(), after.message.c_str());
  LONGS_EQUAL(limit_before, after.value.limit_max_pa);
}
