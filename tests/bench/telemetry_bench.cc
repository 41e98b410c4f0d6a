// Telemetry at full rate: full-8 (8 lines × 1 kHz, batched) from palpa-sim over TCP or a pty for a
// while; frames lost and host CPU per second of stream.
//   palpa_telemetry_bench tcp|pty [SECONDS]             starts its own palpa-sim
//   palpa_telemetry_bench --device URI SECONDS [EVERY]  a full-8 board already running (behind
//                                                       palpa-gadget: usb:, hid:), a sample every
//                                                       EVERY ticks; also what the link carried
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "palpa/host/device.h"
#include "sim_process.h"

namespace {

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_utime.tv_usec / 1e6 + u.ru_stime.tv_sec +
         u.ru_stime.tv_usec / 1e6;
}

/// Counts what the link reads: bytes, and zeros (delimiters, and a HID report's padding).
class CountingTransport final : public palpa::host::Transport {
 public:
  explicit CountingTransport(std::unique_ptr<palpa::host::Transport> t) : t_(std::move(t)) {}
  palpa::protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    const auto n = t_->Read(out, capacity, timeout_ms);
    if (n.ok()) {
      bytes += n.value;
      for (size_t i = 0; i < n.value; ++i) zeros += out[i] == 0 ? 1 : 0;
    }
    return n;
  }
  palpa::host::Status Write(const uint8_t* data, size_t size) override {
    return t_->Write(data, size);
  }
  std::string Describe() const override { return t_->Describe(); }
  std::atomic<uint64_t> bytes{0}, zeros{0};

 private:
  std::unique_ptr<palpa::host::Transport> t_;
};

}  // namespace

int main(int argc, char** argv) {
  const bool on_device = argc > 3 && std::string(argv[1]) == "--device";
  const std::string transport = on_device ? argv[2] : argc > 1 ? argv[1] : "tcp";
  const double seconds = on_device ? std::atof(argv[3]) : argc > 2 ? std::atof(argv[2]) : 60;
  const uint16_t every = on_device && argc > 4 ? static_cast<uint16_t>(std::atoi(argv[4])) : 1;
  const std::string pty = "/tmp/palpa-telemetry-pty-" + std::to_string(getpid());
  palpa::testing::SimProcess sim;
  if (!on_device && !sim.Start({"--config", "full-8", "--speed", "1", "--listen",
                                transport == "pty" ? "pty:" + pty : "tcp:127.0.0.1:0"})) {
    std::fprintf(stderr, "palpa-sim did not start\n");
    return 1;
  }
  auto opened = palpa::host::OpenTransport(on_device ? transport : sim.address());
  if (!opened.ok()) {
    std::fprintf(stderr, "%s\n", opened.message.c_str());
    return 1;
  }
  auto* counting = new CountingTransport(std::move(opened.value));
  auto device = palpa::host::Device::Attach(std::unique_ptr<palpa::host::Transport>(counting), {});
  if (!device.ok()) {
    std::fprintf(stderr, "%s\n", device.message.c_str());
    return 1;
  }
  if (std::string(device.value->info().config_name.data()) != "full-8") {
    std::fprintf(stderr, "%s runs %s, not full-8\n", transport.c_str(),
                 device.value->info().config_name.data());
    return 1;
  }
  device.value->ClearFault();
  auto board = device.value->ReadBoard();
  if (!board.ok()) {
    std::fprintf(stderr, "%s\n", board.message.c_str());
    return 1;
  }
  board.value.telemetry_decimation = every;
  if (!device.value->ConfigureBoard(board.value).ok()) {
    std::fprintf(stderr, "cannot set the telemetry decimation\n");
    return 1;
  }
  std::atomic<uint64_t> frames{0}, samples{0};
  std::atomic<uint32_t> board_dropped{0};
  device.value->Subscribe([&](const palpa::host::TelemetryFrame& f) {
    ++frames;
    samples += f.telemetry.tick_count;
    board_dropped = f.telemetry.dropped_frames;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // settle
  const auto before = device.value->link().counters();
  const uint64_t frames_before = frames, bytes_before = counting->bytes,
                 zeros_before = counting->zeros;
  const double cpu_before = CpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = CpuSeconds() - cpu_before;
  const auto after = device.value->link().counters();
  const uint64_t received = frames - frames_before;
  const double bytes = static_cast<double>(counting->bytes - bytes_before);
  const double padding = static_cast<double>(counting->zeros - zeros_before) -
                         static_cast<double>(after.frames - before.frames);  // zeros past a frame
  std::printf(
      "== telemetry: full-8 (8 lines x 1 kHz, 2 ticks per frame, a sample every %u ticks) "
      "for %.0f s over %s ==\n",
      every, elapsed,
      on_device            ? transport.c_str()
      : transport == "pty" ? "a raw pty"
                           : "TCP (loopback)");
  std::printf("  frames received %llu (%.0f/s), lost on the way %llu, dropped by the board %u\n",
              static_cast<unsigned long long>(received), received / elapsed,
              static_cast<unsigned long long>(after.telemetry_lost - before.telemetry_lost),
              board_dropped.load());
  std::printf("  link read %.0f bytes/s, of which %.0f frame bytes/s", bytes / elapsed,
              (bytes - padding) / elapsed);
  if (transport.rfind("hid:", 0) == 0) {
    std::printf(" in %.0f reports/s (%.1f frame bytes a 64-byte report)", bytes / 64 / elapsed,
                (bytes - padding) / (bytes / 64));
  }
  std::printf("\n  host CPU %.2f %% of one core (reader, dispatcher and heartbeat threads)\n",
              100 * cpu / elapsed);
  device.value.reset();
  if (!on_device) sim.Stop();
  return after.telemetry_lost == before.telemetry_lost ? 0 : 1;
}
