// The signal watch: a thread that waits for SIGINT, SIGTERM and SIGHUP (blocked everywhere else)
// and closes the open sessions before the process ends.
#include "cli_signals.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>

namespace palpa::cli {
namespace {

std::atomic<int> g_signal{0};
std::atomic<int> g_pollers{0};
std::mutex g_mutex;  ///< the devices below, and closing them
std::set<host::Device*> g_devices;

sigset_t Watched() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

/// How long a command that polls Interrupted() has to return by itself.
constexpr auto kGrace = std::chrono::seconds(2);

void Watch() {
  const sigset_t set = Watched();
  int signal = 0;
  if (sigwait(&set, &signal) != 0) return;
  g_signal = signal;
  if (g_pollers.load() > 0) {
    // The command returns by itself and main closes its device on the way out (the process ends
    // and this thread with it); a second signal, or a command that does not, is cut short.
    timespec grace{std::chrono::duration_cast<std::chrono::seconds>(kGrace).count(), 0};
    siginfo_t info;
    sigtimedwait(&set, &info, &grace);
  }
  size_t closed = 0;
  {
    std::lock_guard<std::mutex> lock(g_mutex);
    for (host::Device* d : g_devices) closed += d->link().Close() == protocol::Status::kOk;
  }
  char text[160];
  const int n =
      std::snprintf(text, sizeof(text), "palpa: %s%s\n", strsignal(signal),
                    closed > 0 ? ": the session is closed, the board's outputs are safe" : "");
  if (n > 0 && write(STDERR_FILENO, text, static_cast<size_t>(n)) < 0) {
  }
  _exit(128 + signal);
}

}  // namespace

void StartSignalWatch() {
  const sigset_t set = Watched();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(Watch).detach();
}

bool Interrupted() { return g_signal.load() != 0; }

PollsInterruption::PollsInterruption() { ++g_pollers; }
PollsInterruption::~PollsInterruption() { --g_pollers; }

ClosedOnSignal::ClosedOnSignal(host::Device* device) : device_(device) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_devices.insert(device_);
}

ClosedOnSignal::~ClosedOnSignal() {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_devices.erase(device_);
}

}  // namespace palpa::cli
