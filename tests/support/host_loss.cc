// Host-loss trials against palpa-sim, judged from the simulator's truth side channel.
#include "host_loss.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

#include "mini_client.h"
#include "palpa/host/device.h"
#include "sim_process.h"

namespace palpa::testing {
namespace {

constexpr double kTimeoutUs = 100000;
constexpr double kTickUs = 1000;
constexpr double kSettlingUs = 300000;

/// The child: a host that connects, clears faults, pressurises every line and keeps heartbeating
/// until it is killed (SIGKILL: it cannot close its session, so the board latches host_silence).
[[noreturn]] void Host(const std::string& address, int ready_fd) {
  auto device = host::Device::Open(address, host::DeviceOptions{});
  if (!device.ok()) {
    std::fprintf(stderr, "host loss: the host cannot open the board: %s\n", device.message.c_str());
    _exit(3);
  }
  device.value->ClearFault();
  const host::Outcome o = device.value->SetLines({{0, 80.0}, {1, 80.0}, {2, 80.0}});
  if (!o.ok()) {
    std::fprintf(stderr, "host loss: the board refused the setpoints: %s\n", o.message.c_str());
    _exit(4);
  }
  const char ready = 'A';
  if (write(ready_fd, &ready, 1) != 1) _exit(5);
  for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
}

struct TruthLine {
  double t_us = 0;
  bool safe = false;
  uint32_t faults = 0;
  double last_frame_us = 0;
  double max_command_pa = 0;
  double max_chamber_pa = 0;
};

bool Parse(const std::string& text, TruthLine& out) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.contains("board")) return false;
  out.t_us = j["board_time_us"].get<double>();
  out.safe = j["board"]["safe"].get<bool>();
  out.faults = j["board"]["faults"].get<uint32_t>();
  out.last_frame_us = j["board"]["last_host_frame_us"].get<double>();
  out.max_command_pa = out.max_chamber_pa = 0;
  for (const auto& l : j["lines"]) {
    out.max_command_pa = std::max(out.max_command_pa, std::fabs(l["command_pa"].get<double>()));
    out.max_chamber_pa = std::max(out.max_chamber_pa, std::fabs(l["chamber_pa"].get<double>()));
  }
  return true;
}

/// Reads truth lines for at least `wall_ms`, calling `each` until it returns false.
template <class F>
void ReadTruth(MiniClient& truth, std::string& pending, int wall_ms, F&& each) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(wall_ms);
  while (std::chrono::steady_clock::now() < end) {
    pending += truth.ReadText(20);
    size_t newline;
    while ((newline = pending.find('\n')) != std::string::npos) {
      TruthLine line;
      const bool ok = Parse(pending.substr(0, newline), line);
      pending.erase(0, newline + 1);
      if (ok && !each(line)) return;
    }
  }
}

}  // namespace

HostLossResult RunHostLossTrials(int trials, uint32_t seed, double speed) {
  HostLossResult result;
  SimProcess sim;
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  if (!sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0", "--truth",
                  "tcp:127.0.0.1:0", "--truth-every-ms", "1", "--speed", speed_text})) {
    result.error = "palpa-sim did not start";
    return result;
  }
  MiniClient truth;
  const std::string& t = sim.truth_address();
  if (!truth.ConnectTcp(t.substr(4, t.rfind(':') - 4), std::atoi(t.c_str() + t.rfind(':') + 1))) {
    result.error = "cannot read the truth channel";
    return result;
  }
  std::mt19937 rng(seed);
  std::string pending;
  // A trial whose chambers never filled (the host process was starved and the board went safe on
  // its own before the kill) is not judged and is run again, up to as many extra times.
  for (int trial = 0, attempts = 0; trial < trials && attempts < 2 * trials; ++attempts) {
    int ready[2];
    if (pipe(ready) != 0) break;
    const pid_t child = fork();
    if (child == 0) {
      close(ready[0]);
      Host(sim.address(), ready[1]);
    }
    close(ready[1]);
    char c = 0;
    const bool started = read(ready[0], &c, 1) == 1;
    close(ready[0]);
    if (!started) {
      int status = 0;
      waitpid(child, &status, 0);  // it exited: 3 no session, 4 setpoints refused, 5 no pipe
      result.error = "the host process failed to start (trial " + std::to_string(trial) +
                     ", exit code " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                     ")";
      return result;
    }
    // Let the chambers fill, then kill the host at a random moment.
    bool pressurised = false;
    ReadTruth(truth, pending, 3000,
              [&](const TruthLine& l) { return !(pressurised = l.max_chamber_pa > 50000); });
    std::this_thread::sleep_for(std::chrono::microseconds(rng() % 150000));
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    double last_frame = 0, safe_at = -1, vented_at = -1;
    bool silence = false;
    const int observe_ms = 3000;  // returns as soon as both moments are seen
    ReadTruth(truth, pending, observe_ms, [&](const TruthLine& l) {
      last_frame = std::max(last_frame, l.last_frame_us);
      if (l.t_us <= last_frame) return true;
      if (safe_at < 0 && l.safe && l.max_command_pa == 0) safe_at = l.t_us;
      silence |= (l.faults & 1u) != 0;  // bit 0: host_silence
      if (vented_at < 0 && l.max_chamber_pa < 5000) vented_at = l.t_us;
      return vented_at < 0 || safe_at < 0;
    });
    if (!pressurised) {
      ++result.not_pressurised;
      continue;
    }
    ++trial;
    ++result.trials;
    if (safe_at < 0 || vented_at < 0) {
      ++result.not_observed;
      continue;
    }
    result.host_silence += silence;
    result.safe_after_ms.push_back((safe_at - last_frame) / 1000);
    result.vented_after_ms.push_back((vented_at - last_frame) / 1000);
    result.safe_in_time += safe_at - last_frame <= kTimeoutUs + kTickUs + 1000;
    result.vented_in_time += vented_at - last_frame <= kTimeoutUs + kSettlingUs;
  }
  sim.Stop();
  return result;
}

}  // namespace palpa::testing
