// Transports over a file descriptor: serial ports (termios raw), TCP sockets, and palpa-sim.
#pragma once

#include <sys/types.h>
#include <unistd.h>

#include <string>

#include "palpa/host/device_uri.h"
#include "palpa/host/transport.h"
#include "serial_lock.h"

namespace palpa::host {

class FdTransport : public Transport {
 public:
  FdTransport(int fd, std::string description) : fd_(fd), description_(std::move(description)) {}
  ~FdTransport() override;
  protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override;
  Status Write(const uint8_t* data, size_t size) override;
  std::string Describe() const override { return description_; }

 protected:
  int fd_;
  std::string description_;
};

/// A serial port opened exclusively: its lock file goes when it closes.
class SerialTransport final : public FdTransport {
 public:
  SerialTransport(int fd, std::string description, std::unique_ptr<SerialLock> lock)
      : FdTransport(fd, std::move(description)), lock_(std::move(lock)) {}
  ~SerialTransport() override {
    if (fd_ >= 0) close(fd_);  // the port first, then its lock
    fd_ = -1;
  }

 private:
  std::unique_ptr<SerialLock> lock_;
};

/// A palpa-sim child process and a TCP connection to it; the child is stopped on close.
class SimTransport final : public FdTransport {
 public:
  SimTransport(int fd, pid_t child, std::string description)
      : FdTransport(fd, std::move(description)), child_(child) {}
  ~SimTransport() override;

 private:
  pid_t child_;
};

/// A connected TCP socket with Nagle off, or why not (not_found, unavailable).
Result<int> ConnectTcp(const DeviceUri& uri);

Result<std::unique_ptr<Transport>> OpenSerial(const DeviceUri& uri);
Result<std::unique_ptr<Transport>> OpenTcp(const DeviceUri& uri);
Result<std::unique_ptr<Transport>> OpenSim(const DeviceUri& uri,
                                           std::string* truth_address = nullptr);
Result<std::unique_ptr<Transport>> OpenHid(const DeviceUri& uri);
Result<std::unique_ptr<Transport>> OpenUsb(const DeviceUri& uri);

}  // namespace palpa::host
