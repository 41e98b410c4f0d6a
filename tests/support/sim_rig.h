// The calibration rig in one process on free-running virtual time: a simulated board driven
// through the protocol, and the rig model (stage, indenter, force sensor) of hal/sim stepped with
// the same plant and clock. Faults can be injected: a lost force sensor or stage, an E-stop.
#pragma once

#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "in_process_board.h"
#include "palpa/calibration/rig.h"
#include "palpa/hal/sim/rig_model.h"

namespace palpa::testing {

struct SimRigOptions {
  std::string config = "thesis-5finger";
  uint8_t finger = 0;  ///< the finger under the indenter
  uint32_t unit = 1;
  uint32_t seed = 1;
  sim::Effects effects{};
};

class SimRig final : public calibration::RigTime,
                     public calibration::Stage,
                     public calibration::ForceSensor,
                     public calibration::BoardPort {
 public:
  explicit SimRig(const SimRigOptions& options);

  calibration::Rig rig() { return calibration::Rig{*this, *this, *this, *this}; }
  InProcessBoard& board() { return board_; }
  sim::RigModel& model() { return *model_; }

  // Fault injection.
  bool force_lost = false;
  bool stage_lost = false;
  double force_drift_n_per_s = 0;  ///< the force sensor's zero walks away from its tare
  double force_extra_noise_n = 0;  ///< RMS noise on top of the sensor's own (a worse sensor)
  /// Time that passes before each force reading reaches the host (a busy or slow host): the
  /// stage keeps moving meanwhile.
  double force_latency_s = 0;
  /// The stage stops itself on its load cell (palpa-sim's rig does; a rig file without a
  /// stop_force register does not): off by default, as the host's polling on free-running
  /// virtual time is never late unless force_latency_s says so.
  bool force_stop = false;
  /// The largest true contact force (N) since it was last reset: what the indenter pressed the
  /// finger with, which no reading of the host's may miss.
  float peak_force_n = 0;
  /// The actuator under the indenter changed by this factor since its last calibration.
  void ScaleActuator(float factor);
  /// A line of the board leaks (RegulatorLine::set_leak).
  void Leak(uint8_t line, float ratio) { board_.sim().plant().SetLeak(line, ratio); }

  // RigTime
  double Now() override { return static_cast<double>(board_.sim().now_us()) * 1e-6; }
  void Wait(double seconds) override;
  // Stage
  calibration::RigStatus MoveTo(double mm, double speed_mm_s) override;
  calibration::RigStatus Position(double* mm) override;
  calibration::RigStatus Moving(bool* moving) override;
  calibration::RigStatus Stop() override;
  bool stops_on_force() const override { return force_stop; }
  calibration::RigStatus MoveUntilForce(double mm, double speed_mm_s, double stop_n) override;
  // ForceSensor
  calibration::RigStatus Read(double* newtons) override;
  calibration::RigStatus Tare() override;
  // BoardPort
  bool jamming(uint8_t finger) override;
  uint8_t driven_line(uint8_t finger) override;
  uint8_t bias_line(uint8_t finger) override { return board_.config().fingers[finger].line_a; }
  calibration::RigStatus SetDrive(uint8_t finger, double kpa_a, double kpa_b) override;
  calibration::RigStatus MeasuredKpa(uint8_t line, double* kpa) override;
  calibration::RigStatus LineRangeKpa(uint8_t line, double* kpa) override;
  calibration::RigStatus SetTrim(uint8_t line, bool on) override;
  calibration::RigStatus SetBareLine(uint8_t line, bool bare) override;
  calibration::RigStatus Faults(uint32_t* bitmap) override;
  calibration::RigStatus VentAll() override;

 private:
  InProcessBoard board_;
  uint8_t finger_ = 0;
  double tared_at_s_ = 0;
  std::mt19937 noise_rng_;
  std::unique_ptr<sim::RigModel> model_;
  std::array<protocol::ConfigureLine, protocol::kMaxLines> configured_{};  ///< trims to restore
};

/// The true chamber pressure (Pa) of a finger's driven line through a step of the bare line from
/// `from_kpa` to `to_kpa` (magnitudes; a jamming finger's bias at 20 kPa), on a fresh rig of
/// `options`' unit: (s from the command, Pa), 0.1 s before it to `after_s` after, every
/// millisecond. `outlet`, if given, gets the true pressure at the regulator's outlet alongside.
std::vector<std::pair<double, double>> TrueChamberStep(
    const SimRigOptions& options, double from_kpa, double to_kpa,
    std::vector<std::pair<double, double>>* outlet = nullptr, double after_s = 0.6);

}  // namespace palpa::testing
