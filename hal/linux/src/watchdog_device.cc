// The Linux watchdog API (linux/watchdog.h): ioctls for the timeout and the kick, 'V' to stop.
#include "palpa/hal/linux/watchdog_device.h"

#include <fcntl.h>
#include <linux/watchdog.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace palpa::hal::linux_wdt {
namespace {

// The magic close: the driver stops the timer only when 'V' was the last thing written.
bool MagicClose(int fd) {
  const bool written = write(fd, "V", 1) == 1;
  close(fd);
  return written;
}

}  // namespace

Opened<std::unique_ptr<WatchdogDevice>> WatchdogDevice::Open(const std::string& path,
                                                             int timeout_s) {
  if (timeout_s < 0) {
    return {Status::kOutOfRange,
            path + ": timeout " + std::to_string(timeout_s) + " s (0: the driver's own)"};
  }
  const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    const int why = errno;
    return {why == ENOENT ? Status::kNotFound : Status::kIoError,
            path + ": cannot open the watchdog (" + std::strerror(why) + ")"};
  }
  int status = 0;
  const bool reset_by_watchdog =
      ioctl(fd, WDIOC_GETBOOTSTATUS, &status) == 0 && (status & WDIOF_CARDRESET) != 0;
  if (timeout_s == 0) {  // the driver's own timeout; 0 when `path` cannot tell (not a watchdog)
    int own = 0;
    if (ioctl(fd, WDIOC_GETTIMEOUT, &own) != 0) own = 0;
    return std::unique_ptr<WatchdogDevice>(new WatchdogDevice(path, fd, own, reset_by_watchdog));
  }
  int set = timeout_s;
  if (ioctl(fd, WDIOC_SETTIMEOUT, &set) != 0) {
    const std::string why = path + ": the driver refuses a timeout of " +
                            std::to_string(timeout_s) + " s (" + std::strerror(errno) + ")";
    MagicClose(fd);
    return {Status::kOutOfRange, why};
  }
  int got = 0;
  if (ioctl(fd, WDIOC_GETTIMEOUT, &got) != 0 || got != timeout_s) {
    MagicClose(fd);
    return {Status::kOutOfRange, path + ": asked for a timeout of " + std::to_string(timeout_s) +
                                     " s, the driver has " + std::to_string(got) + " s"};
  }
  return std::unique_ptr<WatchdogDevice>(
      new WatchdogDevice(path, fd, timeout_s, reset_by_watchdog));
}

WatchdogDevice::~WatchdogDevice() {
  if (fd_ >= 0) close(fd_);  // no 'V': the watchdog stays armed
}

bool WatchdogDevice::Kick() {
  if (fd_ < 0) {
    error_ = path_ + ": kicked after Close";
    return false;
  }
  // A write is the keepalive every driver takes (WDIOC_KEEPALIVE is optional), and it leaves a
  // trace in a regular file standing in for the device.
  if (write(fd_, "k", 1) != 1) {
    error_ = path_ + ": keepalive refused (" + std::strerror(errno) + ")";
    return false;
  }
  return true;
}

bool WatchdogDevice::Close() {
  if (fd_ < 0) return true;
  const int fd = fd_;
  fd_ = -1;
  if (!MagicClose(fd)) {
    error_ = path_ + ": writing the magic close failed (" + std::strerror(errno) +
             "); the watchdog stays armed";
    return false;
  }
  return true;
}

}  // namespace palpa::hal::linux_wdt
