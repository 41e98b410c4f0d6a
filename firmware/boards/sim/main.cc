// palpa-sim: the firmware core on the plant model, on a pty or TCP port, in (scaled) real time.
#include <poll.h>
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <utility>
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

/// palpa-sim's parts, opened in order by main and served until a signal stops it.
struct Sim {
  palpa::sim::SimCommandLine cmd;
  palpa::hosted::FdLink link;
  palpa::sim::TruthStream truth;
  std::unique_ptr<palpa::sim::SimBoard> board;
  // Written whole (like every file palpa writes): it appears complete when palpa-sim stops.
  palpa::hal::linux_files::AtomicFile stamps;
  std::unique_ptr<palpa::sim::RigModel> rig;
  palpa::sim::RigModbusServer rig_server;
  palpa::sim::RigNetFtServer netft;
};

/// Prints "palpa-sim: WHY" and returns `code`.
int Failed(const std::string& why, int code) {
  std::fprintf(stderr, "palpa-sim: %s\n", why.c_str());
  return code;
}

/// The board link, the truth channel and the simulated board; an exit code when one cannot open.
int OpenBoard(Sim& s) {
  std::string error;  // the hosted boards' link says it in words
  if (!s.link.Open(s.cmd.listen, &error)) return Failed(error, 1);
  if (!s.cmd.truth.empty()) {
    const palpa::hal::Done opened = s.truth.Open(s.cmd.truth);
    if (!opened.ok()) return Failed(opened.message, 1);
  }
  if (!s.cmd.board.flash_file.empty() && s.cmd.board.boot_nonce == 0) {
    // A board with a past: each start is a new boot, and a host must see a new boot nonce.
    s.cmd.board.boot_nonce = std::random_device{}() | 1u;
  }
  auto board = palpa::sim::SimBoard::Create(s.cmd.board, s.link);
  if (!board.ok()) return Failed(board.message, 2);
  s.board = std::move(board.value);
  return 0;
}

/// --stamp: each stream generation's arrival and DAC write, on CLOCK_MONOTONIC (one clock for
/// host and simulator): "setpoints|targets GENERATION applied|dac NS" lines.
int OpenStamps(Sim& s) {
  if (s.cmd.stamp_file.empty()) return 0;
  const palpa::hal::Done opened = s.stamps.Open(s.cmd.stamp_file);
  if (!opened.ok()) return Failed("--stamp " + opened.message, 1);
  using Stream = palpa::sim::SimBoard::Stream;
  s.board->OnGeneration([&stamps = s.stamps](Stream stream, uint32_t generation, bool dac) {
    timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    char line[80];
    const int n = std::snprintf(line, sizeof(line), "%s %u %s %lld\n",
                                stream == Stream::kTargets ? "targets" : "setpoints", generation,
                                dac ? "dac" : "applied",
                                static_cast<long long>(now.tv_sec) * 1000000000LL + now.tv_nsec);
    stamps.Write(std::string_view(line, static_cast<size_t>(n)));
  });
  return 0;
}

/// --rig-modbus / --rig-netft: the calibration rig on one finger, served beside the board.
int OpenRig(Sim& s) {
  if (s.cmd.rig_modbus.empty() && s.cmd.rig_netft.empty()) return 0;
  if (s.cmd.rig_finger >= s.board->board().config().finger_count) {
    return Failed("--rig-finger " + std::to_string(s.cmd.rig_finger) + ": " + s.cmd.board.config +
                      " has " + std::to_string(s.board->board().config().finger_count) + " fingers",
                  2);
  }
  s.rig = std::make_unique<palpa::sim::RigModel>(s.board->plant(), s.cmd.rig_finger,
                                                 s.cmd.board.plant.seed * 17u + 5u);
  palpa::hal::Done opened;
  if (!s.cmd.rig_modbus.empty()) opened = s.rig_server.Open(s.cmd.rig_modbus, *s.rig);
  if (opened.ok() && !s.cmd.rig_netft.empty()) opened = s.netft.Open(s.cmd.rig_netft, *s.rig);
  return opened.ok() ? 0 : Failed(opened.message, 1);
}

/// What runs where, on stdout: the lines a launcher waits for.
void Announce(const Sim& s) {
  const palpa::sim::SimCommandLine& cmd = s.cmd;
  std::printf("palpa-sim: %s, plant level %d, unit %u, seed %u, speed %gx\n",
              cmd.board.config.c_str(), cmd.board.plant.level, cmd.board.plant.unit,
              cmd.board.plant.seed, static_cast<double>(cmd.speed));
  if (!cmd.board.flash_file.empty()) {
    std::printf(
        "palpa-sim: flash in %s (%s)\n", cmd.board.flash_file.c_str(),
        s.board->board().config_is_default() ? "factory configuration" : "saved configuration");
  }
  std::printf("palpa-sim: listening on %s\n", s.link.address().c_str());
  if (!cmd.truth.empty()) std::printf("palpa-sim: truth on %s\n", s.truth.address().c_str());
  if (!cmd.rig_modbus.empty()) {
    std::printf("palpa-sim: rig (finger %u) by Modbus on %s\n", cmd.rig_finger,
                s.rig_server.address().c_str());
  }
  if (!cmd.rig_netft.empty())
    std::printf("palpa-sim: rig force sensor as Net F/T on %s\n", s.netft.address().c_str());
  std::fflush(stdout);
}

/// The truth stream and the rig, stepped on the board's virtual clock.
void FollowTheBoardClock(Sim& s) {
  if (s.cmd.truth.empty() && !s.rig) return;
  const uint64_t truth_every_us = static_cast<uint64_t>(s.cmd.truth_every_ms) * 1000;
  // Sampled on the virtual clock at every step, so a late process still writes every sample;
  // the rig moves on the same clock.
  s.board->OnStep([&s, truth_every_us](uint64_t now_us) {
    if (s.rig) s.rig->Step(0.001f);
    if (s.cmd.truth.empty() || now_us % truth_every_us != 0) return;
    const palpa::core::Board& b = s.board->board();
    s.truth.Write(
        s.board->plant().Truth(), now_us,
        palpa::sim::TruthStream::BoardFacts{b.safe(), b.latched_faults(), b.last_host_frame_us()});
  });
}

/// The board in (scaled) real time until a signal: inputs, the steps due, outputs, then sleep
/// until the next batch is due or the host or the rig sends something.
void Serve(Sim& s) {
  palpa::sim::SimBoard& sim = *s.board;
  const auto start = std::chrono::steady_clock::now();
  palpa::sim::RealTimePacer pacer(s.cmd.speed);
  std::vector<pollfd> fds;
  uint64_t host_frame_us = 0;        // the board's stamp of the host's last frame
  double host_frame_running_us = 0;  // the running time of the wake that brought it in
  double slept_wall_us = -1;         // the real time of the last wake, which slept...
  double wait_us = 0;                // ...this long at most
  while (!g_stop) {
    const double wall_us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    if (slept_wall_us >= 0) pacer.Woke(slept_wall_us, wait_us, wall_us);
    // Inputs once a wake: a host frame or rig request that arrives mid-batch wakes the next one.
    s.link.Pump();
    s.truth.Pump();
    s.rig_server.Pump();
    s.netft.Serve();
    // The board reads what came in before its clock moves on: a frame that arrived while it was
    // held at the host-silence deadline counts before the next tick can judge the host silent.
    sim.Serve();
    const palpa::core::Board& board = sim.board();
    pacer.HoldToRealTime(palpa::sim::HostNearSilenceTimeout(board.session_open(), sim.now_us(),
                                                            board.last_host_frame_us(),
                                                            board.config().board.host_timeout_us),
                         wall_us, sim.now_us());
    // The host's silence in running time: since the wake that brought its last frame in.
    const double running_us = pacer.RunningUs(wall_us);
    if (board.last_host_frame_us() != host_frame_us) {
      host_frame_us = board.last_host_frame_us();
      host_frame_running_us = running_us;
    }
    const uint64_t limit_us = palpa::sim::HostSilenceLimitUs(board.session_open(), host_frame_us,
                                                             board.config().board.host_timeout_us,
                                                             running_us - host_frame_running_us);
    const uint64_t target_us = std::min(pacer.Target(wall_us, sim.now_us()), limit_us);
    while (sim.now_us() + palpa::sim::RealTimePacer::kStepUs <= target_us && !g_stop) {
      sim.AdvanceTo(sim.now_us() + palpa::sim::RealTimePacer::kStepUs);
      s.netft.Stream();  // one record per board millisecond while streaming
    }
    // Between steps, or held at the host-silence deadline: serves what the host sent, no tick.
    if (target_us > sim.now_us()) {
      sim.AdvanceTo(target_us);
    } else {
      sim.Serve();
    }
    s.link.Pump();  // what the board wrote (the buffer holds far more than a batch)

    // Held at the deadline, the next wake is the host's frame or a step's worth of real time.
    wait_us = sim.now_us() >= limit_us ? palpa::sim::RealTimePacer::kWakeUs
                                       : pacer.WaitUs(wall_us, sim.now_us());
    slept_wall_us = wall_us;
    fds.clear();
    for (int fd : s.link.PollFds()) fds.push_back(pollfd{fd, POLLIN, 0});
    for (int fd : s.rig_server.PollFds()) fds.push_back(pollfd{fd, POLLIN, 0});
    if (s.netft.fd() >= 0) fds.push_back(pollfd{s.netft.fd(), POLLIN, 0});
    const timespec timeout{static_cast<time_t>(wait_us / 1e6),
                           static_cast<long>(std::fmod(wait_us, 1e6) * 1000)};
    ppoll(fds.data(), fds.size(), &timeout, nullptr);
  }
}

/// The stamp file and the truth stream closed whole; 1 when one could not be.
int Finish(Sim& s) {
  int status = 0;
  if (s.stamps.is_open()) {
    const palpa::hal::Done committed = s.stamps.Commit();
    if (!committed.ok()) status = Failed("--stamp " + committed.message, 1);
  }
  if (const palpa::hal::Done closed = s.truth.Close(); !closed.ok())
    status = Failed(closed.message, 1);
  std::printf("palpa-sim: stopped\n");
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Sim s;
  auto parsed = palpa::sim::ParseSimCommandLine(std::vector<std::string>(argv + 1, argv + argc));
  if (!parsed.ok()) {
    std::fprintf(stderr, "palpa-sim: %s\n(see palpa-sim --help)\n", parsed.message.c_str());
    return 2;
  }
  s.cmd = std::move(parsed.value);
  if (s.cmd.help) {
    std::fputs(palpa::sim::kSimUsage, stdout);
    return 0;
  }
  for (const std::string& warning : s.cmd.warnings)
    std::fprintf(stderr, "palpa-sim: warning: %s\n", warning.c_str());
  if (const int rc = OpenBoard(s); rc != 0) return rc;
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  signal(SIGPIPE, SIG_IGN);
  if (const int rc = OpenStamps(s); rc != 0) return rc;
  if (const int rc = OpenRig(s); rc != 0) return rc;
  Announce(s);
  FollowTheBoardClock(s);
  Serve(s);
  return Finish(s);
}
