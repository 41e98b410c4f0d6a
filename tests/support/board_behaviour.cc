// The shared board-behaviour check (CppUTest assertions).
#include "board_behaviour.h"

#include <atomic>
#include <chrono>
#include <thread>

#include "mini_client.h"
#include "palpa/host/device.h"
#include "palpa/host/fault_text.h"
#include "palpa/protocol/faults.h"

#include "CppUTest/TestHarness.h"

namespace palpa::testing {
namespace {

namespace ph = palpa::host;
namespace pp = palpa::protocol;

/// The bare client's bytes through a host transport, so it reaches a board by any device URI.
class TransportPipe final : public BytePipe {
 public:
  explicit TransportPipe(std::unique_ptr<ph::Transport> t) : transport_(std::move(t)) {}
  void Write(const uint8_t* data, size_t size) override { transport_->Write(data, size); }
  long Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    const auto n = transport_->Read(out, capacity, timeout_ms);
    if (n.ok()) return static_cast<long>(n.value);
    return n.status == pp::Status::kTimeout ? 0 : -1;
  }

 private:
  std::unique_ptr<ph::Transport> transport_;
};

}  // namespace

void CheckBoardBehaviour(const std::string& uri, pp::BoardKind kind, bool plant_simulated,
                         uint32_t host_timeout_us) {
  auto opened = ph::Device::Open(uri, {});
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  const pp::HelloReply hello = d.info();
  CHECK(hello.board_kind == kind);
  CHECK(d.link().catalog_matches());
  CHECK(hello.plant_simulated == plant_simulated);  // palpa-linux-board: the plant is real
  STRCMP_EQUAL("thesis-5finger", hello.config_name.data());
  CHECK(d.ClearFault().ok());  // a board a previous host left in host silence takes commands again

  auto board = d.ReadBoard();
  CHECK_TEXT(board.ok(), board.message.c_str());
  board.value.host_timeout_us = host_timeout_us;
  CHECK(d.ConfigureBoard(board.value).ok());

  const ph::Outcome set = d.SetLines({{0, 40.0}});
  CHECK_TEXT(set.ok(), set.message.c_str());
  std::atomic<int32_t> measured{0};
  const int id = d.Subscribe([&](const ph::TelemetryFrame& f) {
    const auto& t = f.telemetry;
    measured = t.samples[(t.tick_count - 1) * t.line_count].measured_pa;
  });
  // Up to 10 s: a board whose module is across a slow network (QEMU's user network, in the
  // real-kernel guest) closes the loop in seconds, not milliseconds.
  for (int i = 0; i < 500 && measured.load() < 39000; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::string why = "line 0 measured " + std::to_string(measured.load()) + " Pa";
  if (measured.load() <= 39000) {  // the board may say why: a fault it latched meanwhile
    const ph::Outcome again = d.SetLines({{0, 40.0}});
    if (!again.ok()) why += "; " + again.message;
  }
  CHECK_TEXT(measured.load() > 39000 && measured.load() < 41000, why.c_str());  // the plant follows

  d.Unsubscribe(id);
  opened.value.reset();

  // Host silence, watched from outside with a bare protocol client: a session with one setpoint,
  // heartbeats while the line is seen actuated, then nothing — every line must go safe with the
  // fault latched. The client heartbeats whenever it waits, as a host does, so a slow link (HID,
  // a loaded machine) delays the checks without cutting the session short.
  MiniClient client;
  auto transport = ph::OpenTransport(uri);
  CHECK_TEXT(transport.ok(), transport.message.c_str());
  client.Use(std::make_unique<TransportPipe>(std::move(transport.value)));
  CHECK(client.Hello(77).ok());
  client.KeepAlive(20);
  LONGS_EQUAL((int)pp::Status::kOk, (int)client.Reliable(pp::ClearFault{}));
  LONGS_EQUAL((int)pp::Status::kOk, (int)client.RawSetpoint(0, 0, 30000));
  auto live = [](const ReceivedFrame& f) {
    return f.Is<pp::Telemetry>() &&
           (f.As<pp::Telemetry>().samples[0].status & pp::line_status::kSafe) == 0;
  };
  int frames = 0;
  pp::Telemetry last{};
  bool seen_live = false;
  for (const auto& f : client.Read(3000, live)) {
    if (!f.Is<pp::Telemetry>()) continue;
    last = f.As<pp::Telemetry>();
    ++frames;
    seen_live |= live(f);
  }
  CHECK_TEXT(
      seen_live,
      (std::to_string(frames) + " telemetry frames, the last with line 1 status " +
       std::to_string(last.samples[0].status) + " at generation " +
       std::to_string(last.setpoint_generation) + ", faults " + ph::FaultNames(last.fault_bitmap))
          .c_str());
  client.KeepAlive(0);
  auto all_safe = [](const ReceivedFrame& f) {
    if (!f.Is<pp::Telemetry>()) return false;
    const auto t = f.As<pp::Telemetry>();
    // The session's last telemetry frame says so, in its last tick: a board sends none after.
    bool all = (t.fault_bitmap & pp::FaultBit(pp::Fault::kHostSilence)) != 0;
    const uint32_t last_tick = (t.tick_count - 1u) * t.line_count;
    for (uint8_t i = 0; i < t.line_count; ++i)
      all &= (t.samples[last_tick + i].status & pp::line_status::kSafe) != 0;
    return all;
  };
  bool safe = false;
  frames = 0;
  std::string others;
  auto read_until_safe = [&] {
    for (const auto& f : client.Read(3000, all_safe)) {
      safe |= all_safe(f);
      if (!f.Is<pp::Telemetry>()) {
        others += " " + std::to_string(f.header.type);
        continue;
      }
      last = f.As<pp::Telemetry>();
      ++frames;
    }
  };
  read_until_safe();
  if (!safe) {
    // A link that drops telemetry (HID at a sample a tick) may lose that last frame: a new
    // session, once the silent one has surely ended, shows the fault latched and every line safe.
    const auto again = client.Hello(78);
    CHECK(again.ok());
    CHECK((again.value.fault_bitmap & pp::FaultBit(pp::Fault::kHostSilence)) != 0);
    client.KeepAlive(20);
    read_until_safe();
    client.KeepAlive(0);
  }
  const uint32_t last_tick = last.tick_count > 0 ? (last.tick_count - 1) * last.line_count : 0;
  CHECK_TEXT(safe,
             (std::to_string(frames) + " telemetry frames after the host went quiet, the " +
              "last with line 1 status " + std::to_string(last.samples[last_tick].status) +
              ", faults " + ph::FaultNames(last.fault_bitmap) + "; other frame types:" + others)
                 .c_str());
}

}  // namespace palpa::testing
