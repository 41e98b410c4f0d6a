// Command → output latency on one monotonic clock: the host stamps the API call, palpa-sim
// (--speed 1) stamps the dispatch and the DAC write of the same setpoint generation.
//   palpa_latency_bench tcp|pty [COMMANDS]            starts its own palpa-sim
//   palpa_latency_bench --device URI --stamps FILE --stop PID [COMMANDS]
//                                                     a palpa-sim already running with --stamp
//                                                     file:FILE (behind palpa-gadget: usb:, hid:),
//                                                     process PID, stopped to read its stamps
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "generation_stamps.h"
#include "mini_client.h"
#include "palpa/host/device.h"
#include "sim_process.h"

namespace pb = palpa::bench;
namespace pp = palpa::protocol;

namespace {

/// Commands with a random phase against the board's tick; returns the host's stamp of each
/// generation.
std::map<uint32_t, int64_t> Measure(palpa::host::Device& d, int commands) {
  d.SetLines({{0, 5.0}});  // raw mode for line 1
  std::map<uint32_t, int64_t> called;
  std::mt19937 rng(1);
  for (int i = 0; i < commands; ++i) {
    std::this_thread::sleep_for(std::chrono::microseconds(rng() % 2000));
    pp::SetLineSetpoints m{};
    m.entry_count = 1;
    m.entries[0] = {0, i % 2 ? 10000 : 20000};
    const int64_t t = pb::MonotonicNs();
    const uint32_t generation = d.link().StreamSetpoints(m);
    called[generation] = t;
    d.link().WaitSetpointsApplied(generation, 200);
  }
  return called;
}

/// The simulator's stamps (its file, complete once it stopped) against the host's.
int Report(const std::string& over, const std::map<uint32_t, int64_t>& called,
           const std::string& stamps, int commands) {
  const pb::LatencySplit l = pb::Match(called, pb::ReadGenerationStamps(stamps, "setpoints"));
  if (l.total.empty()) {
    std::fprintf(stderr, "no stamps matched\n");
    return 1;
  }
  std::printf(
      "== command -> output latency over %s, palpa-sim --speed 1 (%zu of %d commands "
      "stamped) ==\n",
      over.c_str(), l.total.size(), commands);
  pb::PrintLatency("API call -> DAC write", l.total);
  pb::PrintLatency("  of which link (call -> dispatch)", l.link);
  pb::PrintLatency("  of which tick quantisation", l.tick);
  return 0;
}

/// Stops the simulator `pid` and waits until it has gone (its stamp file written whole).
bool StopSim(pid_t pid) {
  if (kill(pid, SIGTERM) != 0) return false;
  for (int i = 0; i < 500 && kill(pid, 0) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return kill(pid, 0) != 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 6 && std::string(argv[1]) == "--device" && std::string(argv[3]) == "--stamps" &&
      std::string(argv[5]) == "--stop") {
    const std::string uri = argv[2], stamps = argv[4];
    const pid_t sim_pid = static_cast<pid_t>(std::atoi(argv[6]));
    const int commands = argc > 7 ? std::atoi(argv[7]) : 1000;
    auto device = palpa::host::Device::Open(uri, {});
    if (!device.ok()) {
      std::fprintf(stderr, "%s\n", device.message.c_str());
      return 1;
    }
    device.value->ClearFault();
    const auto called = Measure(*device.value, commands);
    device.value.reset();
    if (!StopSim(sim_pid)) {
      std::fprintf(stderr, "cannot stop palpa-sim (process %d)\n", static_cast<int>(sim_pid));
      return 1;
    }
    return Report(uri, called, stamps, commands);
  }
  const std::string transport = argc > 1 ? argv[1] : "tcp";
  const int commands = argc > 2 ? std::atoi(argv[2]) : 10000;
  const std::string stamps = "/tmp/palpa-latency-" + std::to_string(getpid()) + ".txt";
  const std::string pty = "/tmp/palpa-latency-pty-" + std::to_string(getpid());
  palpa::testing::SimProcess sim;
  if (!sim.Start({"--config", "thesis-pneumatic-3", "--speed", "1", "--listen",
                  transport == "pty" ? "pty:" + pty : "tcp:127.0.0.1:0", "--stamp",
                  "file:" + stamps})) {
    std::fprintf(stderr, "palpa-sim did not start\n");
    return 1;
  }
  auto device = palpa::host::Device::Open(sim.address(), {});
  if (!device.ok()) {
    std::fprintf(stderr, "%s\n", device.message.c_str());
    return 1;
  }
  const auto called = Measure(*device.value, commands);
  device.value.reset();
  sim.Stop();
  const int status =
      Report(transport == "pty" ? "a raw pty" : "TCP (loopback)", called, stamps, commands);
  std::remove(stamps.c_str());
  return status;
}
