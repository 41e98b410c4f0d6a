// The board and the clock of a rig on lab hardware (or palpa-sim in real time): the board through
// the host library's Device, time from the steady clock scaled by the board's time scale.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
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
};

/// Real time, scaled by the board's time scale (palpa-sim --speed; 1 on hardware).
class ScaledTime final : public RigTime {
 public:
  explicit ScaledTime(double scale)
      : scale_(scale > 0 ? scale : 1), start_(std::chrono::steady_clock::now()) {}
  double Now() override;
  void Wait(double seconds) override;

 private:
  double scale_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace palpa::calibration
