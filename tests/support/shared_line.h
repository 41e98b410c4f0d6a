// One board line shared by several hosts, for tests: a TCP port any number of hosts connect to,
// in front of a board's single TCP link (QEMU's UART). Each host's frames reach the board whole;
// everything the board sends reaches every host — a serial line two programs opened at once.
#pragma once

#include <atomic>
#include <string>
#include <thread>

namespace palpa::testing {

class SharedLine {
 public:
  /// Connects to the board at "tcp:127.0.0.1:PORT" and listens for hosts on a port of its own.
  /// `host_bytes_per_second` > 0: what hosts send reaches the board no faster (a slow line).
  bool Start(const std::string& board_address, int host_bytes_per_second = 0);
  ~SharedLine();
  /// Where hosts connect: "tcp:127.0.0.1:PORT".
  const std::string& address() const { return address_; }

 private:
  void Run();
  int board_fd_ = -1;
  int listen_fd_ = -1;
  int rate_ = 0;
  std::string address_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace palpa::testing
