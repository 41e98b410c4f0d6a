// QEMU's mps2-an386 as a child process with its UART on a TCP port the host library connects to
// (real time); always killed.
#pragma once

#include <string>
#include <vector>

namespace palpa::testing {

class QemuProcess {
 public:
  /// Starts `qemu` with the machine, semihosting and the serial port, plus `args` (-kernel ...,
  /// -device loader,...); true once QEMU listens (the first connection starts its CPU).
  bool Start(const std::string& qemu, const std::vector<std::string>& args);
  ~QemuProcess();
  std::string address() const { return "tcp:127.0.0.1:" + std::to_string(port_); }

 private:
  int port_ = 0;
  int pid_ = -1;
};

}  // namespace palpa::testing
