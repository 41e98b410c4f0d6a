// Prediction: a finger's stiffness arrives a display delay after its target is sent (dead time,
// the regulator's lag, the chamber's), so the scene renders where the hand will be then,
// extrapolated from its recent motion — bounded, and not at all when the motion is erratic.
#pragma once

#include <cstddef>
#include <deque>
#include <string>

#include "palpa/host/outcome.h"
#include "palpa/host/scene_input.h"
#include "palpa/host/scene_render.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::host {

/// A line's dynamics as its calibration configured it: the regulator model's dead time and lag
/// (model_dead_time_us, model_tau_us), the chamber's identified lag behind the outlet
/// (chamber_tau_us: the tube's law's at the calibration step's mean pressure, which depends on
/// the line's kind), the overdrive a shaped step may use (overdrive_pa; 0: steps not shaped) and
/// the line's upper limit (where the board decides whether to lead the regulator).
struct LineDynamics {
  double dead_time_s = 0, regulator_tau_s = 0, chamber_tau_s = 0, overdrive_pa = 0;
  bool vacuum = false;
  double limit_max_pa = 100000;
};
LineDynamics DynamicsOf(const protocol::ConfigureLine& line);

/// The time the board takes to bring the line's chamber half-way through a step of `step_pa`
/// from atmosphere (down on a vacuum line), the calibrated model standing for the plant: the
/// board's own line step (MakeLineParams, StepLine: slew limit, the shaped step's lead and its
/// overdrive held within the line's limits, the chamber estimated from the outlet through the
/// tube's law) run at the board's tick against dead time, the regulator's lag and the tube's law,
/// simulated. Half, because an edge is felt when the stiffness is half-way across it. The
/// regulator has no flow limit: the board's estimate follows the outlet's reading, which this
/// model takes to be the regulator's.
double HalfStepTime(const protocol::ConfigureLine& line, double step_pa);
/// The same for dynamics alone: no slew limit, a sensor on the outlet, limits from atmosphere
/// (from the deepest vacuum on a vacuum line) to limit_max_pa.
double HalfStepTime(const LineDynamics& line, double step_pa);

/// HalfStepTime of a line's calibrated configuration — the calibrated model, never a measurement
/// of the output. A line without a chamber model (chamber_tau_us 0: never calibrated) is
/// unavailable, naming the line.
Result<double> DisplayDelay(const protocol::ConfigureLine& line, double step_pa);

/// The drive (kPa: a pressure, or a vacuum, negative) at which a finger's curve gives `output`
/// (mm of deformation, or N/mm), found on the curve (the calibrated one where loaded).
double DriveForOutput(protocol::FingerKind kind, const FingerCurves& curves, double output);

/// The largest step a scene asks of finger k's line (Pa): from the drive at its softest render
/// to the drive at its stiffest, through its curve — an edge from the softest to the stiffest
/// part of the tissue.
double SceneStepPa(const SceneRenderer& renderer, size_t k);

struct PredictorOptions {
  /// How far ahead to predict: the display's delay (DisplayDelay). Half of the input's own
  /// sample interval is added (a sample is held until the next arrives).
  double horizon_s = 0;
  /// The motion is fitted over this much of the latest input (at least 3 samples).
  double window_s = 0.05;
  /// Never lead the hand by more than this (mm), whatever the speed.
  double max_lead_mm = 2.0;
  /// Erratic: the samples stray from a straight, even motion by more than this (RMS, mm) —
  /// noise, a sharp turn. No prediction then.
  double erratic_rms_mm = 0.15;
  /// Below this speed the hand is stopping or stopped: no prediction (mm/s).
  double stop_speed_mm_s = 3.0;
  /// Samples further apart than this are not one motion (a lifted pen, a stalled stream).
  double max_gap_s = 0.1;
};

/// Outcome problems with options: horizon 0 … 1 s, window 0.005 … 1 s, lead 0 … 50 mm,
/// thresholds ≥ 0, gap > 0.
Outcome CheckPredictor(const PredictorOptions& o);

/// Why a sample was or was not predicted.
enum class Prediction { kPredicted, kTooFewSamples, kErratic, kReversing, kStopped, kLifted };
const char* PredictionName(Prediction p);

class MotionPredictor {
 public:
  explicit MotionPredictor(PredictorOptions options) : o_(options) {}
  /// Takes the latest sample and returns the input to render: its position moved by its
  /// velocity × the horizon (capped at max_lead_mm, held within `extent` where the sample is
  /// within it), or the sample unchanged when there is no safe prediction. Force and time are
  /// the sample's.
  SceneInput Next(const SceneInput& sample);
  /// The tissue's extent: a prediction never leaves it from a sample on it (an edge is not
  /// crossed early into nothing). 0: unbounded.
  void SetExtent(double x_mm, double y_mm) { extent_x_ = x_mm, extent_y_ = y_mm; }
  Prediction last() const { return last_; }
  /// The input the last Next returned (what was rendered).
  const SceneInput& last_output() const { return last_out_; }
  /// How many samples were predicted, and how many were not for each reason (by Prediction).
  size_t count(Prediction p) const { return counts_[static_cast<size_t>(p)]; }
  /// The lead of the last prediction (mm; 0 when none).
  double last_lead_mm() const { return last_lead_; }
  const PredictorOptions& options() const { return o_; }

 private:
  PredictorOptions o_;
  std::deque<SceneInput> history_;
  double extent_x_ = 0, extent_y_ = 0;
  Prediction last_ = Prediction::kTooFewSamples;
  double last_lead_ = 0;
  SceneInput last_out_;
  size_t counts_[6] = {};
  SceneInput Done(Prediction p, const SceneInput& out);
};

}  // namespace palpa::host
