// Telemetry at full rate: full-8 (8 lines × 1 kHz, batched) from palpa-sim over TCP or a pty for a
// while; frames lost and host CPU per second of stream.
//   palpa_telemetry_bench tcp|pty [SECONDS]
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "mini_client.h"
#include "palpa/host/device.h"

namespace {

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_utime.tv_usec / 1e6 + u.ru_stime.tv_sec +
         u.ru_stime.tv_usec / 1e6;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string transport = argc > 1 ? argv[1] : "tcp";
  const double seconds = argc > 2 ? std::atof(argv[2]) : 60;
  const std::string pty = "/tmp/palpa-telemetry-pty-" + std::to_string(getpid());
  palpa::testing::SimProcess sim;
  if (!sim.Start({"--config", "full-8", "--speed", "1", "--listen",
                  transport == "pty" ? "pty:" + pty : "tcp:127.0.0.1:0"})) {
    std::fprintf(stderr, "palpa-sim did not start\n");
    return 1;
  }
  std::string error;
  auto device = palpa::host::Device::Open(sim.address(), {}, &error);
  if (!device.ok()) {
    std::fprintf(stderr, "%s\n", error.c_str());
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
  const uint64_t frames_before = frames;
  const double cpu_before = CpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = CpuSeconds() - cpu_before;
  const auto after = device.value->link().counters();
  const uint64_t received = frames - frames_before;
  std::printf("== telemetry: full-8 (8 lines x 1 kHz, 2 ticks per frame) for %.0f s over %s ==\n",
              elapsed, transport == "pty" ? "a raw pty" : "TCP (loopback)");
  std::printf("  frames received %llu (%.0f/s), lost on the way %llu, dropped by the board %u\n",
              static_cast<unsigned long long>(received), received / elapsed,
              static_cast<unsigned long long>(after.telemetry_lost - before.telemetry_lost),
              board_dropped.load());
  std::printf("  host CPU %.2f %% of one core (reader, dispatcher and heartbeat threads)\n",
              100 * cpu / elapsed);
  device.value.reset();
  sim.Stop();
  return after.telemetry_lost == before.telemetry_lost ? 0 : 1;
}
