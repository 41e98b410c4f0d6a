// A line's chamber dynamics, identified on the rig: the indenter held against the finger (a fixed
// depth into the film, or a fixed press into the jamming material), the force read every
// millisecond through a step of the bare line's drive, and a dead time and the chamber's lag behind
// the regulator's own fitted to it. The board shapes its steps with that lag
// (ConfigureLine::chamber_tau_us).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "palpa/calibration/procedures.h"
#include "palpa/calibration/rig.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::calibration {

/// Dead time, the regulator's lag (given) and the chamber's lag behind it (fitted), in series, to a
/// step response normalised from 0 to 1.
struct ChamberFit {
  double dead_time_s = 0;
  double regulator_tau_s = 0;
  double tau_s = 0;  ///< the chamber's
  double rms = 0;    ///< of the normalised response's residuals (0 … 1: a fraction of the step)
  bool ok = false;
  /// The chamber behind the outlet the board's sensor reads, through a laminar tube
  /// (dC/dt = k (O − C)(O + C + 2 p_atm)): its lag 1 / (2 k (p_ref + p_atm)) at the board's
  /// reference p_ref (core::ChamberStepMeanPa), whatever step found k; 0 where no outlet was
  /// read. And the fit's RMS, as `rms`.
  double outlet_tau_s = 0, outlet_rms = 0;
};

/// Fits (time from the command in s, reading) samples: the reading before the command is the
/// step's start, the mean of its last 50 ms its end; `regulator_tau_s` is the line's regulator
/// model (ConfigureLine::model_tau_us). Not ok when the step is lost in the noise.
ChamberFit FitChamberStep(const std::vector<std::pair<double, double>>& samples,
                          double regulator_tau_s, double noise = 0.0);

/// Fits the tube law's constant to the force samples (as FitChamberStep) and the outlet's
/// readings through the same step ((s, Pa gauge)) of a line of `kind`, a grid of its lag at the
/// board's reference 0.5 % apart; sets fit->outlet_tau_s (that lag) and outlet_rms. The force is
/// taken as the chamber's pressure scaled: from the outlet's before the command to its mean over
/// the last 50 ms.
void FitTubeStep(const std::vector<std::pair<double, double>>& samples,
                 const std::vector<std::pair<double, double>>& outlet, protocol::LineKind kind,
                 ChamberFit* fit);

/// What the fit predicts, 0 … 1 of the step, `t` seconds after the command.
double ChamberResponse(const ChamberFit& fit, double t);

struct ChamberStepOptions {
  double from_kpa = 20, to_kpa = 40;  ///< magnitudes: a vacuum line's drives are negative
  double depth_mm = 0.05;             ///< pneumatic: into the film at the start's surface
  double press_mm = 1.0;              ///< jamming: into the material at the start's surface
  double before_s = 0.1, after_s = 0.6;
  double sample_s = 0.001;        ///< force readings 1 kHz
  double regulator_tau_s = 0.02;  ///< the line's regulator model (model_tau_us)
};

/// The step each kind is identified with: 20 → 40 kPa on a film; 5 → 20 kPa of vacuum under
/// granules, where their air is fastest (deeper, it flows slower: the lag behind the regulator
/// model identified there would lead small steps too far; the tube's lag is the board's
/// reference's from any step). Their mean pressures are the board's reference.
inline ChamberStepOptions ChamberStepFor(bool jamming) {
  ChamberStepOptions o;
  if (jamming) o.from_kpa = 5, o.to_kpa = 20;
  return o;
}

struct ChamberStep {
  ChamberFit fit;  ///< not ok: no model (`why` says why); the run goes on without one
  std::string why;
  std::vector<std::pair<double, double>> samples;  ///< (s from the command on the rig's clock, N)
  std::vector<std::pair<double, double>> outlet;   ///< (s, Pa): the board's sensor, the same times
};

/// Holds the finger's driven line at `from`, finds its surface, presses in, steps the bare line to
/// `to` and reads the force through the step; retracts, restores the line and leaves the finger
/// vented. `zero_mm`: the vented surface (ZeroOnVentedSurface). A step whose readings came slower
/// than 500 Hz, or that the force did not follow, gives no model but is no failure; a limit or a
/// lost device is, as everywhere.
RigStatus MeasureChamberStep(Rig& rig, uint8_t finger, double zero_mm, const ContactOptions& o,
                             const ChamberStepOptions& options, ChamberStep* out);

}  // namespace palpa::calibration
