// Serial and TCP transports on POSIX file descriptors.
#include "fd_transport.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::host {

FdTransport::~FdTransport() {
  if (fd_ >= 0) close(fd_);
}

protocol::Result<size_t> FdTransport::Read(uint8_t* out, size_t capacity, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = poll(&p, 1, timeout_ms);
  if (ready < 0)
    return errno == EINTR ? protocol::Result<size_t>(size_t{0})
                          : protocol::Result<size_t>(Status::kIoError);
  if (ready == 0) return size_t{0};
  const ssize_t n = read(fd_, out, capacity);
  if (n > 0) return static_cast<size_t>(n);
  if (n == 0) return Status::kDisconnected;
  if (errno == EAGAIN || errno == EINTR) return size_t{0};
  return errno == EIO || errno == ECONNRESET ? Status::kDisconnected : Status::kIoError;
}

Status FdTransport::Write(const uint8_t* data, size_t size) {
  size_t at = 0;
  while (at < size) {
    const ssize_t n = ::send(fd_, data + at, size - at, MSG_NOSIGNAL);
    const ssize_t m = n >= 0 || errno != ENOTSOCK ? n : ::write(fd_, data + at, size - at);
    if (m > 0) {
      at += static_cast<size_t>(m);
      continue;
    }
    if (m < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{fd_, POLLOUT, 0};
      if (poll(&p, 1, 1000) == 0) return Status::kTimeout;
      continue;
    }
    return errno == EPIPE || errno == ECONNRESET || errno == EIO ? Status::kDisconnected
                                                                 : Status::kIoError;
  }
  return Status::kOk;
}

namespace {

speed_t BaudConstant(uint32_t baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 921600:
      return B921600;
    case 1000000:
      return B1000000;
    case 2000000:
      return B2000000;
    default:
      return 0;
  }
}

}  // namespace

Result<std::unique_ptr<Transport>> OpenSerial(const DeviceUri& uri) {
  const speed_t speed = BaudConstant(uri.baud);
  if (speed == 0) {
    return {Status::kInvalidArgument,
            "serial:" + uri.path + ": baud " + std::to_string(uri.baud) + " is not supported"};
  }
  // One host per port: the lock file first (it names its holder), then an exclusive open.
  auto lock = std::make_unique<SerialLock>();
  std::string holder;
  if (lock->Acquire(uri.path, &holder) == Status::kBusy) {
    return {Status::kBusy, "busy: another host holds the board (serial:" + uri.path +
                               " is locked by " + holder + ")"};
  }
  const int fd = open(uri.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0 && errno == EBUSY) {  // opened exclusively by a process that took no lock
    holder = SerialHolder(uri.path);
    return {Status::kBusy, "busy: another host holds the board (serial:" + uri.path +
                               " is open exclusively" + (holder.empty() ? "" : " by " + holder) +
                               ")"};
  }
  if (fd < 0) {
    return {errno == ENOENT ? Status::kNotFound : Status::kIoError,
            "serial:" + uri.path + ": " + std::strerror(errno)};
  }
  termios t{};
  if (tcgetattr(fd, &t) != 0) {
    const std::string why =
        "serial:" + uri.path + ": not a terminal (" + std::strerror(errno) + ")";
    close(fd);
    return {Status::kInvalidArgument, why};
  }
  cfmakeraw(&t);
  cfsetispeed(&t, speed);
  cfsetospeed(&t, speed);
  t.c_cflag |= CLOCAL | CREAD;
  tcsetattr(fd, TCSANOW, &t);
  tcflush(fd, TCIOFLUSH);
  MakeExclusive(fd);  // a second open by anyone but root now fails with EBUSY
  return std::unique_ptr<Transport>(new SerialTransport(fd, "serial:" + uri.path, std::move(lock)));
}

Result<int> ConnectTcp(const DeviceUri& uri) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string where = "tcp:" + uri.host + ":" + std::to_string(uri.port);
  if (getaddrinfo(uri.host.c_str(), std::to_string(uri.port).c_str(), &hints, &found) != 0 ||
      found == nullptr) {
    return {Status::kNotFound, where + ": unknown host"};
  }
  int fd = -1;
  for (addrinfo* a = found; a != nullptr && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd >= 0 && connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      close(fd);
      fd = -1;
    }
  }
  const int saved = errno;
  freeaddrinfo(found);
  if (fd < 0) {
    return {Status::kUnavailable, where + ": " + std::strerror(saved)};
  }
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return fd;
}

Result<std::unique_ptr<Transport>> OpenTcp(const DeviceUri& uri) {
  const Result<int> fd = ConnectTcp(uri);
  if (!fd.ok()) return fd.outcome();
  return std::unique_ptr<Transport>(
      new FdTransport(fd.value, "tcp:" + uri.host + ":" + std::to_string(uri.port)));
}

}  // namespace palpa::host
