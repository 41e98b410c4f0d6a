// Calibration procedures on a Rig: contact detection and zeroing, regulator static correction,
// deformation sweeps (pneumatic), presses and indentation grids (jamming). Every motion is
// guarded: a force above the limit, a position beyond the stage's limits, a board fault or a lost
// device stops the stage, retracts, vents the board and returns the reason.
#pragma once

#include <limits>
#include <utility>
#include <vector>

#include "palpa/calibration/hysteresis_fit.h"
#include "palpa/calibration/rig.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::calibration {

struct ContactOptions {
  double speed_mm_s = 0.1;    ///< the thesis's indentation speed
  double threshold_n = 0.01;  ///< contact: the force crosses this
  double approach_mm = 0.3;   ///< a fast move stops this far above the expected surface
  double fast_mm_s = 2.0;
  /// Touches averaged per reading of a deformation sweep: the rig repeats to 2.82 % per reading
  /// (thesis Table 5-4's protocol, which averaged five repeats per point), so one touch would put
  /// that much scatter into every point the fits see.
  int touches = 5;
};

/// Moves to `mm` at `speed` and waits until the stage stops, polling force and position every
/// `poll_s`; any limit aborts (stop, retract, vent).
RigStatus GuardedMove(Rig& rig, double mm, double speed_mm_s, double poll_s = 0.01);

/// Stops the stage, retracts to the safe height and vents the board: the one way out of a run.
RigStatus AbortSafe(Rig& rig, host::Status status, const std::string& why);

/// Approaches from `expected_mm` + approach and creeps down until contact; returns the encoder
/// position at contact (the surface height), then lifts clear by the approach distance. A creep
/// faster than 0.1 mm/s only locates the surface: the last stretch is crept again at 0.1 mm/s from
/// above it, so a host that sees contact late costs a tenth of the depth.
RigStatus FindSurface(Rig& rig, double expected_mm, const ContactOptions& o, double* surface_mm);

/// Tares the force sensor clear of the finger, vents it and finds the vented surface (the zero).
/// With `noise_n`, also the RMS of a second of readings after the tare (the sensor's noise).
RigStatus ZeroOnVentedSurface(Rig& rig, uint8_t finger, const ContactOptions& o, double* zero_mm,
                              double* noise_n = nullptr);

/// The mean of `count` readings 10 ms apart (and their RMS spread), wherever the indenter is.
RigStatus ReadForceMean(Rig& rig, int count, double* mean_n, double* rms_n = nullptr);

/// The force clear of everything, the sensor's zero as the end of a run reads it: the indenter
/// at the retract height, the mean of 10 readings.
RigStatus ReadClearForce(Rig& rig, double fast_mm_s, double* force_n, double* rms_n = nullptr);

/// Before a measurement that finds a surface by the contact threshold (`before`, the run's step):
/// reads the zero clear of everything into `clear_n` (NaN if it could not be read). At or over
/// the threshold a surface search reads contact wherever the indenter is: the run stops
/// (AbortSafe, `walked` set) naming the zero, its reading and the limit — unless the readings
/// spread beyond the noise check's limit, where the mean may be noise (that check's to report).
RigStatus CheckZeroBefore(Rig& rig, const ContactOptions& o, const std::string& before,
                          double* clear_n, bool* walked);

/// Regulator static correction of one of the finger's lines: trim off, commands up and down in
/// `points` steps over 10–90 % of the line's range, the settled sensor reading at each (the other
/// line of a jamming finger held at its working value). Trim back on after.
RigStatus RegulatorCorrection(Rig& rig, uint8_t finger, uint8_t line, int points, double dwell_s,
                              std::vector<protocol::CorrectionPoint>* out);

/// Pneumatic: each drive (kPa) held for dwell_s, the surface found by contact detection; samples
/// of (measured drive in Pa, deformation in µm above `zero_mm`). Each drive's search starts from
/// the surface found at the one before; the first's from `expected_mm` (the zero if NaN), so a
/// sweep resumed point by point starts from its last point's surface, not from the vented film's,
/// which a film inflated by millimetres would put the indenter that deep into.
RigStatus DeformationSweep(Rig& rig, uint8_t finger, const std::vector<double>& kpa, double dwell_s,
                           double zero_mm, const ContactOptions& o, std::vector<SweepSample>* out,
                           double expected_mm = std::numeric_limits<double>::quiet_NaN());

/// One press of a jamming finger: down to `depth_mm` below the surface and back at `speed`.
struct PressCycle {
  double stiffness_n_per_mm = 0;  ///< Hooke's-law slope at contact (F = k·d + q·d² on loading)
  double r2 = 0;                  ///< of that fit
  double loop_area_mj = 0;        ///< between loading and unloading (N·mm = mJ)
  double peak_force_n = 0;
  double residual_n = 0;  ///< RMS of the loading fit's residuals: the force sensor's noise, mostly
  double free_force_n = 0;  ///< mean reading just clear of the surface before the press: its zero
  std::vector<std::pair<double, double>> loading, unloading;  ///< (depth mm, force N)
};
RigStatus Press(Rig& rig, double surface_mm, double depth_mm, double speed_mm_s, PressCycle* out);

/// Least-squares line y = a + b·x with R².
struct Line {
  double slope = 0, intercept = 0, r2 = 0;
};
Line FitLine(const std::vector<std::pair<double, double>>& xy);

}  // namespace palpa::calibration
