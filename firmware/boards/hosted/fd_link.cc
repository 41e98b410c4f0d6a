// TCP, pty and serial-device transports for the hosted boards.
#include "fd_link.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pty.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "tcp_listener.h"

namespace palpa::hosted {
namespace {

void NonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK); }

/// Where the link at `path` points ("" when it is not a link).
std::string LinkTarget(const std::string& path) {
  char target[256];
  const ssize_t n = readlink(path.c_str(), target, sizeof(target) - 1);
  return n > 0 ? std::string(target, static_cast<size_t>(n)) : std::string();
}

}  // namespace

FdLink::~FdLink() {
  for (Peer& c : clients_) close(c.fd);
  if (listen_fd_ >= 0) close(listen_fd_);
  if (pty_slave_ >= 0) close(pty_slave_);
  // Only the link this process made: whatever someone put there meanwhile stays.
  if (!symlink_.empty() && LinkTarget(symlink_) == pty_name_) unlink(symlink_.c_str());
}

bool FdLink::MayReplace(const std::string& spec, std::string* error) const {
  struct stat st;
  if (lstat(symlink_.c_str(), &st) != 0) return true;  // nothing there
  const std::string target = S_ISLNK(st.st_mode) ? LinkTarget(symlink_) : "";
  if (target.rfind("/dev/pts/", 0) != 0) {
    *error = option_ + " " + spec + ": " + symlink_ +
             " exists and is not a pty link (only a link to a pty that is gone is replaced; "
             "remove it or choose another path)";
    return false;
  }
  if (stat(symlink_.c_str(), &st) == 0) {
    *error = option_ + " " + spec + ": " + symlink_ + " links to " + target +
             ", a pty in use (another board?)";
    return false;
  }
  return true;  // a link left by a board that was killed
}

bool FdLink::Open(const std::string& spec, std::string* error, const char* option, int baud) {
  option_ = option;
  if (spec.rfind("tcp:", 0) == 0) {
    listen_fd_ = ListenTcp(spec, option, &address_, error);
    return listen_fd_ >= 0;
  }
  if (spec.rfind("pty:", 0) == 0) return OpenPty(spec, error);
  if (spec.rfind("tty:", 0) == 0) return OpenTty(spec, baud, error);
  *error = option_ + " " + spec + ": expected tcp:HOST:PORT, pty:PATH or tty:DEVICE";
  return false;
}

bool FdLink::OpenPty(const std::string& spec, std::string* error) {
  symlink_ = spec.substr(4);
  if (symlink_.empty()) {
    *error = option_ + " " + spec + ": expected pty:PATH";
    return false;
  }
  if (!MayReplace(spec, error)) {
    symlink_.clear();
    return false;
  }
  int master = -1;
  char name[256];
  if (openpty(&master, &pty_slave_, name, nullptr, nullptr) != 0) {
    *error = option_ + " " + spec + ": openpty: " + std::strerror(errno);
    symlink_.clear();
    return false;
  }
  pty_name_ = name;
  termios raw{};
  tcgetattr(pty_slave_, &raw);
  cfmakeraw(&raw);
  tcsetattr(pty_slave_, TCSANOW, &raw);
  unlink(symlink_.c_str());  // a stale pty link, checked above; symlink() then never clobbers
  if (symlink(name, symlink_.c_str()) != 0) {
    *error = option_ + " " + spec + ": cannot create the symlink: " + std::strerror(errno);
    symlink_.clear();
    close(master);
    return false;
  }
  NonBlocking(master);
  clients_.push_back(Peer{master, {}, {}});
  is_pty_ = true;
  address_ = "serial:" + symlink_;
  return true;
}

bool FdLink::OpenTty(const std::string& spec, int baud, std::string* error) {
  const std::string device = spec.substr(4);
  const int fd = device.empty() ? -1 : open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) {
    *error = option_ + " " + spec + ": " +
             (device.empty() ? std::string("expected tty:DEVICE") : std::strerror(errno));
    return false;
  }
  termios raw{};
  if (tcgetattr(fd, &raw) != 0) {
    *error = option_ + " " + spec + ": not a serial device (" + std::strerror(errno) + ")";
    close(fd);
    return false;
  }
  cfmakeraw(&raw);
  raw.c_cflag |= CLOCAL | CREAD;  // no modem lines: a board's UART has none
  const speed_t speed = baud == 9600     ? B9600
                        : baud == 19200  ? B19200
                        : baud == 38400  ? B38400
                        : baud == 57600  ? B57600
                        : baud == 230400 ? B230400
                        : baud == 460800 ? B460800
                        : baud == 921600 ? B921600
                                         : B115200;
  cfsetspeed(&raw, speed);
  tcsetattr(fd, TCSANOW, &raw);
  clients_.push_back(Peer{fd, {}, {}});
  is_pty_ = true;
  address_ = "serial:" + device;
  return true;
}

bool FdLink::ReadFrom(Peer& peer) {
  uint8_t buffer[4096];
  // Bounded: a host that sends faster than the board reads waits (TCP and the pty push back).
  while (rx_.size() - rx_read_ < kRxCapacity) {
    const ssize_t n = read(peer.fd, buffer, sizeof(buffer));
    if (n == 0 && !is_pty_) return false;  // the host closed the connection
    if (n <= 0) return true;               // EAGAIN, or EIO on a pty with no client
    for (ssize_t i = 0; i < n; ++i) {
      peer.partial.push_back(buffer[i]);
      if (buffer[i] == 0) {  // a whole frame: to the board, never interleaved with another's
        rx_.insert(rx_.end(), peer.partial.begin(), peer.partial.end());
        peer.partial.clear();
      } else if (peer.partial.size() > kMaxPartial) {
        peer.partial.clear();
      }
    }
  }
  return true;
}

void FdLink::WriteTo(Peer& peer) {
  while (!peer.tx.empty()) {
    const ssize_t n = write(peer.fd, peer.tx.data(), peer.tx.size());
    if (n <= 0) break;
    peer.tx.erase(peer.tx.begin(), peer.tx.begin() + n);
  }
  if (is_pty_ && peer.tx.size() > kTxCapacity / 2) peer.tx.clear();  // nobody reading the pty
}

void FdLink::Pump() {
  for (int client; listen_fd_ >= 0 && (client = accept(listen_fd_, nullptr, nullptr)) >= 0;) {
    if (clients_.size() >= kMaxClients) {  // a board has few hosts; the rest are turned away
      close(client);
      continue;
    }
    NonBlocking(client);
    const int one = 1;
    setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    clients_.push_back(Peer{client, {}, {}});
  }
  for (size_t i = 0; i < clients_.size();) {
    if (ReadFrom(clients_[i])) {
      WriteTo(clients_[i]);
      ++i;
    } else {
      close(clients_[i].fd);
      clients_.erase(clients_.begin() + static_cast<long>(i));
    }
  }
}

std::vector<int> FdLink::PollFds() const {
  std::vector<int> fds;
  for (const Peer& c : clients_) fds.push_back(c.fd);
  if (listen_fd_ >= 0) fds.push_back(listen_fd_);
  return fds;
}

size_t FdLink::DoRead(uint8_t* out, size_t capacity) {
  size_t n = 0;
  while (n < capacity && rx_read_ < rx_.size()) out[n++] = rx_[rx_read_++];
  if (rx_read_ == rx_.size()) {
    rx_.clear();
    rx_read_ = 0;
  }
  return n;
}

size_t FdLink::DoWrite(const uint8_t* data, size_t size) {
  if (clients_.empty()) return size;  // no host: the bytes go nowhere, as on an unplugged UART
  const size_t n = size < DoWriteSpace() ? size : DoWriteSpace();
  // Every host hears the board; one that reads too slowly loses what does not fit its buffer
  // (its decoder resynchronises at the next delimiter) without holding back the others.
  for (Peer& c : clients_) {
    const size_t fits = kTxCapacity - c.tx.size() < n ? kTxCapacity - c.tx.size() : n;
    c.tx.insert(c.tx.end(), data, data + fits);
  }
  return n;
}

size_t FdLink::DoWriteSpace() const {
  size_t emptiest = kTxCapacity;  // back-pressure follows the host that keeps up best
  for (const Peer& c : clients_) emptiest = c.tx.size() < emptiest ? c.tx.size() : emptiest;
  return clients_.empty() ? kTxCapacity : kTxCapacity - emptiest;
}

}  // namespace palpa::hosted
