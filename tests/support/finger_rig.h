// One finger of a simulated board on a simulated rig, in-process on virtual time: identification
// sweeps in raw mode (lines in their service loop), compensators configured through the protocol,
// targets followed in target mode, outputs read by the rig model and, for scoring only, the truth.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "in_process_board.h"
#include "palpa/calibration/hysteresis_fit.h"
#include "palpa/calibration/procedures.h"
#include "palpa/calibration/sweep.h"
#include "palpa/hal/sim/rig_measurement.h"
#include "palpa/host/outcome.h"

namespace palpa::testing {

struct FingerRigOptions {
  uint8_t finger = 0;      ///< thesis-5finger: 0-2 pneumatic, 3-4 jamming
  uint32_t unit = 1;       ///< actuator unit (0 nominal; others drawn with the thesis's spread)
  uint32_t seed = 1;       ///< regulators, sensors, rig noise
  sim::Effects effects{};  ///< creep, rate, jamming history size
};

class FingerRig {
 public:
  explicit FingerRig(const FingerRigOptions& options);

  bool jamming() const { return jamming_; }
  /// Largest drive the driven line allows (Pa, magnitude).
  double drive_max() const { return drive_max_; }

  /// Raw mode: each drive held for dwell_ms, then the measured drive (the line's sensor) and the
  /// rig's reading of the output (finger unit: µm or mN/mm).
  std::vector<calibration::SweepSample> Sweep(const std::vector<double>& drives, int dwell_ms);

  /// Sends the finger's configuration with a static inverse and compensator; the board's answer
  /// (with its reason when it refuses).
  host::Outcome Configure(const std::vector<protocol::InversePoint>& inverse,
                          protocol::CompensatorKind kind, const std::vector<float>& params);

  /// Target mode: sets the target (finger unit) and runs `ms`, calling `each_ms` after every step.
  void Follow(double target, int ms, const std::function<void(double truth)>& each_ms = nullptr);
  /// The true output now, in the finger's unit (scoring only).
  double TruthOutput() const;
  /// Whether the driven line reported the compensator (or pipeline) saturated on the last tick.
  bool Saturated() const;
  sim::SimBoard& sim() { return board_.sim(); }

 private:
  double MeasuredDrive() const;
  double RigOutput();

  FingerRigOptions options_;
  InProcessBoard board_;
  sim::RigMeasurement rig_;
  bool jamming_ = false;
  uint8_t driven_line_ = 0;
  double drive_max_ = 100000;
  bool target_mode_ = false;
};

}  // namespace palpa::testing
