// A test's child process, stopped however the test ends.
#pragma once

#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>

namespace palpa::testing {

/// Owns a forked child: a failed check leaves the test by an exception, and a child left running
/// (a socat, a Modbus server) would keep the test's output open and CTest waiting for it for ever.
class ChildProcess {
 public:
  explicit ChildProcess(pid_t pid, int signal = SIGTERM) : pid_(pid), signal_(signal) {}
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() { Stop(); }

  pid_t pid() const { return pid_; }

  /// Sends the signal and waits for the child; its wait status, or -1 once it is gone.
  int Stop() {
    if (pid_ <= 0) return -1;
    kill(pid_, signal_);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return status;
  }

 private:
  pid_t pid_;
  int signal_;
};

}  // namespace palpa::testing
