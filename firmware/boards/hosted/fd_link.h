// A hosted board's link to the host (palpa-sim, palpa-linux-board): a pseudo-terminal, a serial
// device, or TCP connections — up to eight, as hosts sharing one line: each host's frames reach the
// board whole, and everything the board sends reaches every host (so a second host hears busy, and
// the first sees it lose the board). Bounded transmit buffers, so back-pressure is real.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "palpa/hal/byte_link.h"

namespace palpa::hosted {

class FdLink final : public hal::ByteLink {
 public:
  ~FdLink();

  /// "tcp:HOST:PORT" (PORT 0 picks a free port), "pty:PATH" (creates a pty and a symlink to
  /// it at PATH; something already at PATH is replaced only when it is a link to a pty that is
  /// gone, and on exit only the link this process made is removed) or "tty:DEVICE" (a serial
  /// device that exists: a UART, a gadget's ACM port, a pty's slave side; raw 8N1 at `baud`).
  /// `option` names the setting in messages ("--listen", "link.listen"). Returns false with
  /// *error on failure.
  bool Open(const std::string& spec, std::string* error, const char* option = "--listen",
            int baud = 115200);
  /// Where a host connects: "tcp:127.0.0.1:40123" or "serial:/path/to/link".
  const std::string& address() const { return address_; }

  /// Accepts waiting clients, reads what has arrived, writes what is queued. Never blocks.
  void Pump();
  /// File descriptors worth waiting on (listener, clients, pty), for poll().
  std::vector<int> PollFds() const;
  bool connected() const { return is_pty_ || !clients_.empty(); }

 private:
  size_t DoRead(uint8_t* out, size_t capacity) override;
  size_t DoWrite(const uint8_t* data, size_t size) override;
  size_t DoWriteSpace() const override;

  struct Peer {
    int fd = -1;
    std::vector<uint8_t> partial;  ///< bytes of a frame not yet ended by its delimiter
    std::vector<uint8_t> tx;
  };
  /// Reads what `peer` sent; complete frames go to the board. False when it hung up.
  bool ReadFrom(Peer& peer);
  void WriteTo(Peer& peer);
  bool MayReplace(const std::string& spec, std::string* error) const;
  bool OpenPty(const std::string& spec, std::string* error);
  bool OpenTty(const std::string& spec, int baud, std::string* error);

  static constexpr size_t kTxCapacity = 64 * 1024;
  static constexpr size_t kRxCapacity = 64 * 1024;
  static constexpr size_t kMaxClients = 8;     ///< TCP hosts at once (more are closed on arrival)
  static constexpr size_t kMaxPartial = 4096;  ///< a "frame" longer than this is noise: dropped
  int listen_fd_ = -1;
  std::vector<Peer> clients_;  ///< TCP connections, or the pty master alone
  int pty_slave_ = -1;         ///< kept open so the master never sees a hang-up between clients
  bool is_pty_ = false;        ///< a pty or a serial device: one peer, never hung up
  std::string option_ = "--listen";
  std::string symlink_;
  std::string pty_name_;  ///< /dev/pts/N, where symlink_ points
  std::string address_;
  std::vector<uint8_t> rx_;
  size_t rx_read_ = 0;
};

}  // namespace palpa::hosted
