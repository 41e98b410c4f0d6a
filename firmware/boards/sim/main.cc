// palpa-sim: the firmware core on the plant model, on a pty or TCP port, in (scaled) real time.
#include <poll.h>
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "fd_link.h"
#include "palpa/hal/linux/atomic_file.h"
#include "real_time_pacer.h"
#include "rig_modbus_server.h"
#include "rig_netft_server.h"
#include "sim_board.h"
#include "sim_options.h"
#include "truth_stream.h"

namespace {

volatile sig_atomic_t g_stop = 0;

void OnSignal(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv) {
  using palpa::sim::SimCommandLine;
  SimCommandLine cmd;
  std::string error;
  if (!palpa::sim::ParseSimCommandLine(std::vector<std::string>(argv + 1, argv + argc), cmd,
                                       &error)) {
    std::fprintf(stderr, "palpa-sim: %s\n(see palpa-sim --help)\n", error.c_str());
    return 2;
  }
  if (cmd.help) {
    std::fputs(palpa::sim::kSimUsage, stdout);
    return 0;
  }
  for (const std::string& warning : cmd.warnings)
    std::fprintf(stderr, "palpa-sim: warning: %s\n", warning.c_str());
  palpa::sim::FdLink link;
  if (!link.Open(cmd.listen, &error)) {
    std::fprintf(stderr, "palpa-sim: %s\n", error.c_str());
    return 1;
  }
  palpa::sim::TruthStream truth;
  if (!cmd.truth.empty() && !truth.Open(cmd.truth, &error)) {
    std::fprintf(stderr, "palpa-sim: %s\n", error.c_str());
    return 1;
  }
  if (!cmd.board.flash_file.empty() && cmd.board.boot_nonce == 0) {
    // A board with a past: each start is a new boot, and a host must see a new boot nonce.
    cmd.board.boot_nonce = std::random_device{}() | 1u;
  }
  auto sim = palpa::sim::SimBoard::Create(cmd.board, link, &error);
  if (!sim) {
    std::fprintf(stderr, "palpa-sim: %s\n", error.c_str());
    return 2;
  }
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  signal(SIGPIPE, SIG_IGN);

  // Written whole (like every file palpa writes): it appears complete when palpa-sim stops.
  palpa::hal::linux_files::AtomicFile stamps;
  if (!cmd.stamp_file.empty()) {
    if (!stamps.Open(cmd.stamp_file, &error)) {
      std::fprintf(stderr, "palpa-sim: --stamp %s\n", error.c_str());
      return 1;
    }
    // One monotonic clock for host and simulator: CLOCK_MONOTONIC nanoseconds.
    sim->OnSetpointGeneration([&stamps](uint32_t generation, bool dac) {
      timespec now;
      clock_gettime(CLOCK_MONOTONIC, &now);
      char line[64];
      const int n =
          std::snprintf(line, sizeof(line), "%u %s %lld\n", generation, dac ? "dac" : "applied",
                        static_cast<long long>(now.tv_sec) * 1000000000LL + now.tv_nsec);
      stamps.Write(std::string_view(line, static_cast<size_t>(n)));
    });
  }
  std::unique_ptr<palpa::sim::RigModel> rig;
  palpa::sim::RigModbusServer rig_server;
  palpa::sim::RigNetFtServer netft;
  if (!cmd.rig_modbus.empty() || !cmd.rig_netft.empty()) {
    if (cmd.rig_finger >= sim->board().config().finger_count) {
      std::fprintf(stderr, "palpa-sim: --rig-finger %u: %s has %u fingers\n", cmd.rig_finger,
                   cmd.board.config.c_str(), sim->board().config().finger_count);
      return 2;
    }
    rig = std::make_unique<palpa::sim::RigModel>(sim->plant(), cmd.rig_finger,
                                                 cmd.board.plant.seed * 17u + 5u);
    if ((!cmd.rig_modbus.empty() && !rig_server.Open(cmd.rig_modbus, *rig, &error)) ||
        (!cmd.rig_netft.empty() && !netft.Open(cmd.rig_netft, *rig, &error))) {
      std::fprintf(stderr, "palpa-sim: %s\n", error.c_str());
      return 1;
    }
  }
  std::printf("palpa-sim: %s, plant level %d, unit %u, seed %u, speed %gx\n",
              cmd.board.config.c_str(), cmd.board.plant.level, cmd.board.plant.unit,
              cmd.board.plant.seed, static_cast<double>(cmd.speed));
  if (!cmd.board.flash_file.empty()) {
    std::printf("palpa-sim: flash in %s (%s)\n", cmd.board.flash_file.c_str(),
                sim->board().config_is_default() ? "factory configuration" : "saved configuration");
  }
  std::printf("palpa-sim: listening on %s\n", link.address().c_str());
  if (!cmd.truth.empty()) std::printf("palpa-sim: truth on %s\n", truth.address().c_str());
  if (!cmd.rig_modbus.empty()) {
    std::printf("palpa-sim: rig (finger %u) by Modbus on %s\n", cmd.rig_finger,
                rig_server.address().c_str());
  }
  if (!cmd.rig_netft.empty())
    std::printf("palpa-sim: rig force sensor as Net F/T on %s\n", netft.address().c_str());
  std::fflush(stdout);

  const uint64_t truth_every_us = static_cast<uint64_t>(cmd.truth_every_ms) * 1000;
  if (!cmd.truth.empty() || rig) {
    // Sampled on the virtual clock at every step, so a late process still writes every sample;
    // the rig moves on the same clock.
    sim->OnStep([&](uint64_t now_us) {
      if (rig) rig->Step(0.001f);
      if (cmd.truth.empty() || now_us % truth_every_us != 0) return;
      const palpa::core::Board& b = sim->board();
      truth.Write(sim->plant().Truth(), now_us,
                  palpa::sim::TruthStream::BoardFacts{b.safe(), b.latched_faults(),
                                                      b.last_host_frame_us()});
    });
  }
  const auto start = std::chrono::steady_clock::now();
  palpa::sim::RealTimePacer pacer(cmd.speed);
  std::vector<pollfd> fds;
  uint64_t host_frame_us = 0;     // the board's stamp of the host's last frame
  double host_frame_wall_us = 0;  // the real time of the wake that brought it in
  while (!g_stop) {
    const double wall_us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    // Inputs once a wake: a host frame or rig request that arrives mid-batch wakes the next one.
    link.Pump();
    truth.Pump();
    rig_server.Pump();
    netft.Serve();
    // The board reads what came in before its clock moves on: a frame that arrived while it was
    // held at the host-silence deadline counts before the next tick can judge the host silent.
    sim->Serve();
    const palpa::core::Board& board = sim->board();
    pacer.HoldToRealTime(palpa::sim::HostNearSilenceTimeout(board.session_open(), sim->now_us(),
                                                            board.last_host_frame_us(),
                                                            board.config().board.host_timeout_us),
                         wall_us, sim->now_us());
    // The host's silence in real time: since the wake that brought its last frame in.
    if (board.last_host_frame_us() != host_frame_us) {
      host_frame_us = board.last_host_frame_us();
      host_frame_wall_us = wall_us;
    }
    const uint64_t limit_us = palpa::sim::HostSilenceLimitUs(board.session_open(), host_frame_us,
                                                             board.config().board.host_timeout_us,
                                                             wall_us - host_frame_wall_us);
    const uint64_t target_us = std::min(pacer.Target(wall_us, sim->now_us()), limit_us);
    while (sim->now_us() + palpa::sim::RealTimePacer::kStepUs <= target_us && !g_stop) {
      sim->AdvanceTo(sim->now_us() + palpa::sim::RealTimePacer::kStepUs);
      netft.Stream();  // one record per board millisecond while streaming
    }
    // Between steps, or held at the host-silence deadline: serves what the host sent, no tick.
    if (target_us > sim->now_us()) {
      sim->AdvanceTo(target_us);
    } else {
      sim->Serve();
    }
    link.Pump();  // what the board wrote (the buffer holds far more than a batch)

    // Sleep until the next batch of steps is due, or until the host or the rig sends something.
    // Held at the deadline, the next wake is the host's frame or a step's worth of real time.
    const double wait_us = sim->now_us() >= limit_us ? palpa::sim::RealTimePacer::kWakeUs
                                                     : pacer.WaitUs(wall_us, sim->now_us());
    fds.clear();
    for (int fd : link.PollFds()) fds.push_back(pollfd{fd, POLLIN, 0});
    for (int fd : rig_server.PollFds()) fds.push_back(pollfd{fd, POLLIN, 0});
    if (netft.fd() >= 0) fds.push_back(pollfd{netft.fd(), POLLIN, 0});
    const timespec timeout{static_cast<time_t>(wait_us / 1e6),
                           static_cast<long>(std::fmod(wait_us, 1e6) * 1000)};
    ppoll(fds.data(), fds.size(), &timeout, nullptr);
  }
  int status = 0;
  if (stamps.is_open() && !stamps.Commit(&error)) {
    std::fprintf(stderr, "palpa-sim: --stamp %s\n", error.c_str());
    status = 1;
  }
  if (!truth.Close(&error)) {
    std::fprintf(stderr, "palpa-sim: %s\n", error.c_str());
    status = 1;
  }
  std::printf("palpa-sim: stopped\n");
  return status;
}
