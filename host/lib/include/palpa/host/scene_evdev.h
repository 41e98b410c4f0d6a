// A pen tablet or touchpad read through libevdev (/dev/input/eventN): each complete report
// (SYN_REPORT) becomes one scene input, mapped onto the tissue; reports lost in the kernel's
// buffer (SYN_DROPPED) are re-read from the device's state instead of being guessed.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "palpa/host/outcome.h"
#include "palpa/host/scene_tablet.h"

struct libevdev;

namespace palpa::host {

class PenTablet {
 public:
  /// Opens `path` (an evdev node) and maps it onto a tissue of the given extent. A device that is
  /// not a pad (no absolute x or y) is refused naming the device and what it lacks; one without
  /// a pressure axis is accepted and presses with `touch_force_n` while it touches.
  static Result<std::unique_ptr<PenTablet>> Open(const std::string& path, double extent_x_mm,
                                                 double extent_y_mm, PressureForce pressure_force,
                                                 double touch_force_n = 1.0);
  ~PenTablet();
  PenTablet(const PenTablet&) = delete;
  PenTablet& operator=(const PenTablet&) = delete;

  /// Waits up to `timeout_ms` for the next complete report and returns it as an input (time: the
  /// report's kernel time stamp on CLOCK_MONOTONIC); nothing when none came in time. A device
  /// that went away (unplugged) is io_error naming it.
  Result<std::optional<SceneInput>> Next(int timeout_ms);

  const TabletMapping& mapping() const { return mapping_; }
  /// The last report's pressure level (0 … 1 023; 0 without a pressure axis) and contact.
  double last_level() const { return last_level_; }
  bool last_touching() const { return last_touching_; }
  /// Reports re-read after the kernel dropped events (SYN_DROPPED), since opening.
  size_t resyncs() const { return resyncs_; }

 private:
  PenTablet(std::string path, int fd, libevdev* dev, TabletMapping mapping)
      : path_(std::move(path)), fd_(fd), dev_(dev), mapping_(std::move(mapping)) {}
  SceneInput Current(double time_s);

  std::string path_;
  int fd_ = -1;
  libevdev* dev_ = nullptr;
  TabletMapping mapping_;
  size_t resyncs_ = 0;
  double last_level_ = 0;
  bool last_touching_ = false;
};

}  // namespace palpa::host
