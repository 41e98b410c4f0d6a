// The simulated board's link to the host: a non-blocking file descriptor behind a TCP listener
// or a pseudo-terminal, with a bounded transmit buffer so back-pressure is real.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "palpa/hal/byte_link.h"

namespace palpa::sim {

class FdLink final : public hal::ByteLink {
 public:
  ~FdLink();

  /// "tcp:HOST:PORT" (PORT 0 picks a free port) or "pty:PATH" (creates a pty and a symlink to
  /// it at PATH; something already at PATH is replaced only when it is a link to a pty that is
  /// gone, and on exit only the link this process made is removed). Returns false with *error on
  /// failure.
  bool Open(const std::string& spec, std::string* error);
  /// Where a host connects: "tcp:127.0.0.1:40123" or "serial:/path/to/link".
  const std::string& address() const { return address_; }

  /// Accepts a waiting client, reads what has arrived, writes what is queued. Never blocks.
  void Pump();
  /// File descriptors worth waiting on (listener or client, pty), for poll().
  std::vector<int> PollFds() const;
  bool connected() const { return io_fd_ >= 0; }

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override;
  size_t DoWrite(const uint8_t* data, size_t size) override;
  size_t DoWriteSpace() const override;
  void Disconnect();
  bool MayReplace(const std::string& spec, std::string* error) const;

  static constexpr size_t kTxCapacity = 64 * 1024;
  static constexpr size_t kRxCapacity = 64 * 1024;
  int listen_fd_ = -1;
  int io_fd_ = -1;      ///< TCP client, or the pty master
  int pty_slave_ = -1;  ///< kept open so the master never sees a hang-up between clients
  bool is_pty_ = false;
  std::string symlink_;
  std::string pty_name_;  ///< /dev/pts/N, where symlink_ points
  std::string address_;
  std::vector<uint8_t> rx_;
  size_t rx_read_ = 0;
  std::vector<uint8_t> tx_;
};

}  // namespace palpa::sim
