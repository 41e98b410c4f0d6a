// The host library's link and device against palpa-sim: streams under faults, subscribers that
// stall or unsubscribe, configuration and recordings, a real pty, heartbeats that follow a shorter
// host timeout, staged configurations.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "config_record.h"
#include "mini_client.h"
#include "palpa/host/device.h"
#include "palpa/host/fault_text.h"
#include "palpa/host/fault_transport.h"
#include "palpa/host/link.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

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

/// The board's latched faults in words, for failure messages.
std::string LatchedFaults(ph::Device& device) {
  const auto diagnostics = device.Diagnostics();
  return diagnostics.ok() ? "latched: " + ph::FaultNames(diagnostics.value.fault_bitmap)
                          : "no diagnostics";
}

}  // namespace

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
