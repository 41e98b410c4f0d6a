// Pen tablets through libevdev: the pad's axes and pressure read from the device's state at each
// SYN_REPORT, and a resynchronisation after SYN_DROPPED (libevdev's sync mode) instead of a report
// assembled from half of the lost events.
#include "palpa/host/scene_evdev.h"

#include <fcntl.h>
#include <libevdev/libevdev.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace palpa::host {
namespace {

PadAxis Axis(libevdev* dev, unsigned code) {
  const input_absinfo* a = libevdev_get_abs_info(dev, code);
  return a == nullptr ? PadAxis{} : PadAxis{a->minimum, a->maximum, a->resolution};
}

double Seconds(const timeval& t) { return t.tv_sec + t.tv_usec * 1e-6; }

}  // namespace

Result<std::unique_ptr<PenTablet>> PenTablet::Open(const std::string& path, double extent_x_mm,
                                                   double extent_y_mm, PressureForce pressure_force,
                                                   double touch_force_n) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return {Status::kIoError, path + ": " + std::strerror(errno)};
  libevdev* dev = nullptr;
  if (const int rc = libevdev_new_from_fd(fd, &dev); rc < 0) {
    ::close(fd);
    return {Status::kIoError, path + ": not an input event device (" + std::strerror(-rc) + ")"};
  }
  const char* name = libevdev_get_name(dev);
  const std::string device = path + " (\"" + (name != nullptr ? name : "") + "\")";
  std::string missing;
  for (const auto& [code, what] :
       {std::pair{ABS_X, "absolute x axis (ABS_X)"}, std::pair{ABS_Y, "absolute y axis (ABS_Y)"}}) {
    if (!libevdev_has_event_code(dev, EV_ABS, code))
      missing += (missing.empty() ? "" : " and no ") + std::string(what);
  }
  if (!missing.empty()) {
    libevdev_free(dev);
    ::close(fd);
    return {Status::kInvalidArgument,
            device + " is not a pen tablet or touchpad: it has no " + missing +
                " (a mouse reports relative motion, which cannot place a hand on a tissue)"};
  }
  libevdev_set_clock_id(dev, CLOCK_MONOTONIC);
  TabletMapping m;
  m.pad.name = name != nullptr ? name : path;
  m.pad.x = Axis(dev, ABS_X);
  m.pad.y = Axis(dev, ABS_Y);
  if (libevdev_has_event_code(dev, EV_ABS, ABS_PRESSURE)) m.pad.pressure = Axis(dev, ABS_PRESSURE);
  m.pad.has_touch = libevdev_has_event_code(dev, EV_KEY, BTN_TOUCH);
  m.extent_x_mm = extent_x_mm;
  m.extent_y_mm = extent_y_mm;
  m.pressure_force = pressure_force;
  m.touch_force_n = touch_force_n;
  if (Outcome ok = CheckTabletMapping(m); !ok.ok()) {
    libevdev_free(dev);
    ::close(fd);
    ok.message = path + ": " + ok.message;
    return ok;
  }
  return std::unique_ptr<PenTablet>(new PenTablet(path, fd, dev, std::move(m)));
}

PenTablet::~PenTablet() {
  libevdev_free(dev_);
  if (fd_ >= 0) ::close(fd_);
}

SceneInput PenTablet::Current(double time_s) {
  const int x = libevdev_get_event_value(dev_, EV_ABS, ABS_X);
  const int y = libevdev_get_event_value(dev_, EV_ABS, ABS_Y);
  std::optional<int> pressure;
  if (mapping_.pad.pressure) pressure = libevdev_get_event_value(dev_, EV_ABS, ABS_PRESSURE);
  // Contact: BTN_TOUCH where the pad reports it; otherwise any pressure above the axis's minimum.
  const bool touching = mapping_.pad.has_touch
                            ? libevdev_get_event_value(dev_, EV_KEY, BTN_TOUCH) != 0
                            : pressure && *pressure > mapping_.pad.pressure->minimum;
  last_level_ = pressure ? PressureLevel(*mapping_.pad.pressure, *pressure) : 0.0;
  last_touching_ = touching;
  return MapPad(mapping_, time_s, x, y, pressure, touching);
}

Result<std::optional<SceneInput>> PenTablet::Next(int timeout_ms) {
  using Sample = Result<std::optional<SceneInput>>;
  pollfd p{fd_, POLLIN, 0};
  bool waited = false;
  for (;;) {
    input_event ev{};
    int rc = libevdev_next_event(dev_, LIBEVDEV_READ_FLAG_NORMAL, &ev);
    if (rc == LIBEVDEV_READ_STATUS_SYNC) {
      // The kernel dropped events: libevdev gives the differences to the device's present state;
      // read them all (its state is then current) and report that state once.
      ++resyncs_;
      double t = Seconds(ev.time);
      while ((rc = libevdev_next_event(dev_, LIBEVDEV_READ_FLAG_SYNC, &ev)) ==
             LIBEVDEV_READ_STATUS_SYNC) {
        t = Seconds(ev.time);
      }
      if (rc != -EAGAIN && rc < 0) break;
      return Sample(Current(t));
    }
    if (rc == LIBEVDEV_READ_STATUS_SUCCESS) {
      if (ev.type == EV_SYN && ev.code == SYN_REPORT) return Sample(Current(Seconds(ev.time)));
      continue;  // part of a report: libevdev keeps the state, the report ends it
    }
    if (rc != -EAGAIN) break;
    if (waited) return Sample(std::nullopt);
    const int ready = ::poll(&p, 1, timeout_ms);
    if (ready < 0 && errno != EINTR) break;
    if (ready > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
      return Sample(Status::kIoError,
                    path_ + " (\"" + mapping_.pad.name + "\"): the device is gone");
    }
    waited = ready <= 0;  // timed out (or interrupted): one more read, then nothing
  }
  return Sample(Status::kIoError,
                path_ + " (\"" + mapping_.pad.name + "\"): reading failed, the device is gone");
}

}  // namespace palpa::host
