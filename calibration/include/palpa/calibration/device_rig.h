// The board and the clock of a rig on lab hardware (or palpa-sim in real time): the board through
// the host library's Device, time from the board's clock in its telemetry.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>

#include "palpa/calibration/rig.h"
#include "palpa/host/device.h"

namespace palpa::calibration {

class DeviceBoardPort final : public BoardPort {
 public:
  explicit DeviceBoardPort(host::Device& device);
  ~DeviceBoardPort() override;
  bool jamming(uint8_t finger) override;
  uint8_t driven_line(uint8_t finger) override;
  uint8_t bias_line(uint8_t finger) override { return device_.info().fingers[finger].line_a; }
  RigStatus SetDrive(uint8_t finger, double kpa_a, double kpa_b) override;
  RigStatus MeasuredKpa(uint8_t line, double* kpa) override;
  RigStatus LineRangeKpa(uint8_t line, double* kpa) override;
  RigStatus SetTrim(uint8_t line, bool on) override;
  RigStatus SetBareLine(uint8_t line, bool bare) override;
  RigStatus Faults(uint32_t* bitmap) override;
  RigStatus VentAll() override;

 private:
  host::Device& device_;
  int subscription_ = 0;
  std::mutex mutex_;
  std::array<double, protocol::kMaxLines> measured_kpa_{};
  uint32_t faults_ = 0;
  double last_frame_s_ = 0;
  std::array<protocol::ConfigureLine, protocol::kMaxLines> configured_{};
  std::array<bool, protocol::kMaxLines> known_{};
  /// The line's configuration as read at first use, edited, sent.
  RigStatus Reconfigure(uint8_t line, const std::function<void(protocol::ConfigureLine&)>& edit);
};

/// The board's own clock, read from its telemetry: a wait lasts as long in board time as asked,
/// whatever real time that takes. On hardware board time is real time; palpa-sim runs at its
/// --speed but slips when the machine is busy and returns to real time while the host is near
/// its silence timeout, and a dwell counted in scaled real time would then end early.
class BoardTime final : public RigTime {
 public:
  explicit BoardTime(host::Device& device);
  ~BoardTime() override;
  /// Seconds of board time since the first telemetry frame (0 before it).
  double Now() override;
  /// Until the board's clock has advanced `seconds`, however slowly it runs. Ended early only
  /// when the clock stops for a second of real time (telemetry lost: link lost, board reset),
  /// and the rig's checks then say why. Before the first frame: scaled real time.
  void Wait(double seconds) override;

 private:
  host::Device& device_;
  double scale_;
  int subscription_ = 0;
  std::mutex mutex_;
  std::condition_variable advanced_;
  bool seen_ = false;
  uint64_t last_us_ = 0;              ///< the newest sample's board time
  uint64_t elapsed_us_ = 0;           ///< board time since the first frame, across board resets
  uint64_t wake_at_us_ = UINT64_MAX;  ///< the waiting thread's end (one waiter: the procedure)
};

}  // namespace palpa::calibration
