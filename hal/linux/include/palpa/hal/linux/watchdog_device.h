// A Linux watchdog device (/dev/watchdog): armed when opened, kicked by the controller after each
// tick that wrote its outputs; only a deliberate Close stops it.
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "palpa/hal/linux/opened.h"

namespace palpa::hal::linux_wdt {

class WatchdogDevice {
 public:
  /// Opens `path` (which starts the watchdog) and sets its timeout, read back from the driver;
  /// `timeout_s` 0 keeps the driver's own. A failure names the path and the reason: kNotFound (no
  /// such device), kIoError (it cannot be opened), kOutOfRange (a negative timeout, or one the
  /// driver refuses or changes; the watchdog is then stopped again, by magic close, before
  /// returning). A regular file is taken too (with timeout 0): the host tests read the kicks ('k')
  /// and the magic close ('V') from it.
  static Opened<std::unique_ptr<WatchdogDevice>> Open(const std::string& path, int timeout_s);
  /// Without Close(): the device is closed without the magic character and stays armed, so the
  /// machine resets unless another program takes the watchdog over in time.
  ~WatchdogDevice();
  WatchdogDevice(const WatchdogDevice&) = delete;
  WatchdogDevice& operator=(const WatchdogDevice&) = delete;

  /// Restarts the timeout (writes 'k'). false, with error() set, when the driver refused.
  bool Kick();
  /// Clean stop: writes the magic 'V' and closes, which stops the watchdog (unless the kernel
  /// was built or loaded with nowayout). false, with error() set, when the write failed.
  bool Close();
  int timeout_s() const { return timeout_s_; }  ///< 0: not known (not a watchdog driver)
  /// The driver reported that the last reset was the watchdog's (WDIOF_CARDRESET at open).
  bool reset_by_watchdog() const { return reset_by_watchdog_; }
  const std::string& error() const { return error_; }

 private:
  WatchdogDevice(std::string path, int fd, int timeout_s, bool reset_by_watchdog)
      : path_(std::move(path)),
        fd_(fd),
        timeout_s_(timeout_s),
        reset_by_watchdog_(reset_by_watchdog) {}
  std::string path_;
  int fd_;
  int timeout_s_;
  bool reset_by_watchdog_;
  std::string error_;
};

}  // namespace palpa::hal::linux_wdt
