// palpa-sim (or another program that announces its addresses the same way) as a child process of
// a test, and free ports on the loopback for servers that cannot pick their own.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace palpa::testing {

/// A TCP or UDP port on 127.0.0.1 that was free a moment ago (for servers that cannot pick their
/// own, and for a test's datagrams).
int FreeTcpPort();
int FreeUdpPort();

/// palpa-sim as a child process; stopped with SIGTERM when destroyed. Its output is read for its
/// whole life (a thread after Start), so a child that writes much never blocks on a full pipe.
class SimProcess {
 public:
  SimProcess();
  /// Starts PALPA_SIM_PATH (or `program`: another board, or a server, that announces itself the
  /// same way) with the arguments and waits up to `timeout_ms` for its "listening on" line.
  bool Start(const std::vector<std::string>& args, const char* program = nullptr,
             int timeout_ms = 5000);
  ~SimProcess();
  /// Sends SIGTERM and returns the exit status (-1 if it had to be killed).
  int Stop();
  /// Waits up to `timeout_ms` for it to exit by itself (or by a signal the test sent): its exit
  /// status, -1 when a signal ended it, -2 when it is still running.
  int WaitExit(int timeout_ms);
  const std::string& address() const {
    return address_;
  }  ///< "tcp:127.0.0.1:PORT" or "serial:PATH"
  const std::string& truth_address() const { return truth_address_; }  ///< when --truth was given
  const std::string& rig_address() const { return rig_address_; }  ///< when --rig-modbus was given
  const std::string& netft_address() const {
    return netft_address_;
  }  ///< when --rig-netft was given
  int pid() const { return pid_; }
  /// What it printed (stdout and stderr) until Start returned: its addresses, its warnings, or
  /// why it refused to start.
  const std::string& output() const { return output_; }
  /// What it printed after Start returned, the last 64 KiB of it: for a failure's message.
  std::string later_output() const;

 private:
  struct Drain;
  std::unique_ptr<Drain> drain_;
  int pid_ = -1;
  int out_fd_ = -1;
  std::string address_;
  std::string truth_address_;
  std::string rig_address_;
  std::string netft_address_;
  std::string output_;
};

}  // namespace palpa::testing
