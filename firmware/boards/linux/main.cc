// palpa-linux-board: the firmware core on a Linux computer at 1 kHz, with the regulators and
// sensors on a Modbus analogue I/O module, valves and the E-stop on GPIO, the host on TCP,
// serial or USB device mode.
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <utility>

#include "board_file.h"
#include "host_link.h"
#include "linux_io.h"
#include "palpa/hal/linux/modbus_aio.h"
#include "palpa/hal/linux/watchdog_device.h"
#include "process_claim.h"
#include "realtime.h"

namespace {

namespace lb = palpa::linux_board;

const char kUsage[] =
    "usage: palpa-linux-board BOARD.json\n"
    "\n"
    "Runs the palpa firmware core at 1 kHz on this computer: the analogue I/O module, GPIO\n"
    "lines, host link and watchdog the file names (docs/linux.md). SIGTERM or SIGINT writes\n"
    "every output safe and exits 0.\n";

volatile sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

int Failed(const std::string& why, int code) {
  std::fprintf(stderr, "palpa-linux-board: %s\n", why.c_str());
  return code;
}

/// The lock file for the analogue I/O module: a serial bus is one program's whatever the unit
/// (the device's real path, so that two names of one port are one), a Modbus TCP module its
/// address (resolved: hal::linux_aio::ResolveModuleHost), port and unit.
std::string ModuleClaimPath(const palpa::hal::linux_aio::ModbusAioConfig& m) {
  std::string key =
      "tcp:" + m.host + ":" + std::to_string(m.port) + " unit " + std::to_string(m.unit);
  if (!m.tcp) {
    char* real = realpath(m.host.c_str(), nullptr);
    key = "rtu:" + std::string(real != nullptr ? real : m.host.c_str());
    std::free(real);
  }
  return palpa::hosted::RunDirectory("palpa-linux-board") + "/" + palpa::hosted::LockFileName(key) +
         ".lock";
}

/// The tick statistics the core keeps (also reported over the link by GetLoopStats).
void ReportTicks(const palpa::core::TickStats& t) {
  std::printf(
      "palpa-linux-board: %llu ticks, %u overruns, jitter max %u us, tick mean %.1f us, worst "
      "%u us\n",
      static_cast<unsigned long long>(t.ticks), t.overruns, t.jitter_max_us,
      t.ticks > 0 ? static_cast<double>(t.busy_us) / static_cast<double>(t.ticks) : 0.0,
      t.worst_tick_us);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc != 2) return Failed("expected one argument, the board file (see --help)", 2);
  auto loaded = lb::LoadBoardFile(argv[1]);
  if (!loaded.ok()) return Failed(loaded.message, 2);
  lb::BoardFile& file = loaded.value;
  if (file.module.tcp) {
    // Resolved once, for the claim and the connection both, so that `localhost` and `127.0.0.1`
    // are one module (a second lookup of a name with several addresses may order them otherwise).
    auto address = palpa::hal::linux_aio::ResolveModuleHost(file.module.host);
    if (!address.ok()) {
      return Failed(std::string(argv[1]) + ": analog_module.host: " + address.message, 1);
    }
    file.module.host = address.value;
  }

  struct sigaction action {};
  action.sa_handler = OnSignal;  // no SA_RESTART: the tick's sleep returns, the loop ends
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  signal(SIGPIPE, SIG_IGN);

  // The module is claimed before anything is opened: a second board started on the same module
  // (its GPIO lines different or none) is refused here, before it writes 0 V to the outputs the
  // first one drives or rewrites its watchdog. Held until exit; the kernel drops it on any death.
  palpa::hosted::ProcessClaim module_claim;
  std::string claim_error;  // the hosted boards' claim says it in words
  if (!module_claim.Take(ModuleClaimPath(file.module), "analog_module " + file.module.Describe(),
                         &claim_error))
    return Failed(claim_error, 1);
  auto opened_io = lb::LinuxIo::Open(file);
  if (!opened_io.ok()) return Failed(opened_io.message, 1);
  const std::unique_ptr<lb::LinuxIo> io = std::move(opened_io.value);
  // Below, a start that fails writes the outputs safe first; its own failure is not the one
  // reported (the module's watchdog zeroes the outputs anyway).
  lb::HostLink link;
  if (const palpa::hal::Done opened = link.Open(file.listen, file.baud); !opened.ok()) {
    io->WriteSafe();
    return Failed(opened.message, 1);
  }
  std::unique_ptr<palpa::hal::linux_wdt::WatchdogDevice> watchdog;
  if (!file.watchdog.empty()) {
    auto opened =
        palpa::hal::linux_wdt::WatchdogDevice::Open(file.watchdog, file.watchdog_timeout_s);
    if (!opened.ok()) {
      io->WriteSafe();
      return Failed("watchdog.device: " + opened.message, 1);
    }
    watchdog = std::move(opened.value);
  }
  const lb::RealTimeReport rt = lb::EnterRealTime(file.rt_priority);

  palpa::core::BoardIdentity id;
  id.kind = palpa::protocol::BoardKind::kLinux;
  id.board_id = file.board_id;
  id.boot_nonce = std::random_device{}() | 1u;  // each start is a new boot to a host
  id.rx_buffer_bytes = 4096;
  palpa::core::Board board(*file.config, io->Io(link.link()), id);
  board.Start();

  const auto& m = file.module;
  std::printf(
      "palpa-linux-board: %s, analogue I/O %s (%s, %u outputs, %u inputs), %zu GPIO lines%s\n",
      file.board.c_str(), m.Describe().c_str(), m.module->name, m.output_count, m.input_count,
      io->gpio_lines(), io->gpio_lines() == 0 ? " (none configured)" : "");
  std::printf("palpa-linux-board: real time: %s\n", rt.Describe(file.rt_priority).c_str());
  if (watchdog) {
    std::printf("palpa-linux-board: watchdog %s, %d s\n", file.watchdog.c_str(),
                watchdog->timeout_s());
  }
  if (link.stale_gadget_removed())
    std::printf("palpa-linux-board: removed the USB gadget a program that died left behind\n");
  if (!link.udc().empty()) std::printf("palpa-linux-board: USB gadget on %s\n", link.udc().c_str());
  std::printf("palpa-linux-board: listening on %s\n", link.address().c_str());
  std::fflush(stdout);

  // The grid starts where the core's tick pacer did (Board::Start read the same clock just now).
  lb::DeadlineGrid grid(lb::MonotonicNs(), palpa::core::Board::kTickUs * 1000u);
  while (!g_stop) {
    if (!grid.Sleep()) continue;  // a signal: the loop condition decides
    link.Pump();
    if (board.Step() && watchdog) watchdog->Kick();  // only after a tick wrote its outputs
    link.Pump();
    grid.Advance(lb::MonotonicNs());
  }
  const palpa::hal::Done safe = io->WriteSafe();
  // After the outputs are safe: a failure above still leaves the reset armed.
  if (watchdog && !watchdog->Close()) Failed(watchdog->error(), 1);
  ReportTicks(board.tick_stats());
  if (!safe.ok()) return Failed("writing the safe outputs: " + safe.message, 1);
  std::printf("palpa-linux-board: outputs safe, stopped\n");
  return 0;
}
