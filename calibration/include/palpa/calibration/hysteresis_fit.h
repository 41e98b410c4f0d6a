// Identification of hysteresis compensators from a quasi-static sweep: constrained least squares
// (non-negative operator weights, monotone branches), residuals reported, parameters in the
// layout ConfigureFinger accepts. Shared by the hysteresis benchmarks and calibration procedures.
#pragma once

#include <string>
#include <vector>

#include "palpa/calibration/play_operators.h"
#include "palpa/host/outcome.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::calibration {

/// One settled point of a sweep: the drive the line's sensor measured (Pa ≥ 0: pressure, or
/// vacuum magnitude) and the actuator's output as the rig measured it (finger's output unit).
struct SweepSample {
  double drive_pa = 0;
  double output = 0;
};

struct HysteresisFit {
  protocol::CompensatorKind kind = protocol::CompensatorKind::kNone;
  std::vector<float> params;  ///< ConfigureFinger.params layout (docs/hysteresis.md)
  double residual_rms = 0;    ///< output units; for branch, the drive residual in Pa
  double residual_max = 0;
  /// pi and api: the operators fitted, and how many of them carry a weight (the others were
  /// driven to zero by the non-negative least squares: the sweep gave them nothing to explain).
  int operators = 0, operators_used = 0;
  std::string error;  ///< non-empty: no usable fit, and why
  bool ok() const { return error.empty(); }
};

/// Dead zones of an `api` fit: four knots of S are what the evidence in docs/hysteresis.md used.
constexpr int kApiDeadZones = 4;

/// The settled readings a sweep needs for a pi or api fit of `operators` (api with
/// kApiDeadZones): twice the unknowns' count, about; 0 for other kinds.
size_t MinSweepPoints(protocol::CompensatorKind kind, int operators);
/// The most operators (up to 32) a pi or api fit can have on a sweep of `points` readings; 0 when
/// even one is too many.
int MaxOperators(protocol::CompensatorKind kind, size_t points);

/// Checks a sweep before fitting: enough points, finite, drive within 0..drive_max.
std::string SweepError(const std::vector<SweepSample>& sweep, size_t min_points, double drive_max);

HysteresisFit FitPi(const std::vector<SweepSample>& sweep, int operators, double drive_max);
HysteresisFit FitApi(const std::vector<SweepSample>& sweep, int operators, int dead_zones,
                     double drive_max);
/// Rising and falling curves at `points` output levels; the reversal band chosen on the sweep.
HysteresisFit FitBranch(const std::vector<SweepSample>& sweep, int points);

/// The better play model on this sweep: api when it fits and leaves at most three quarters of
/// pi's RMS residual (its dead zones must earn their extra cost per step), else pi. `comparison`
/// says what was compared ("api(16): 9.1 against pi(16): 58.7 um RMS").
HysteresisFit FitBetterPlayModel(const std::vector<SweepSample>& sweep, int operators,
                                 double drive_max, std::string* comparison);

/// The fit of one compensator kind: `size` operators (pi, api) or curve points (branch); `none`
/// is an empty parameter set.
HysteresisFit FitCompensator(protocol::CompensatorKind kind, int size,
                             const std::vector<SweepSample>& sweep, double drive_max);

/// The static inverse (none): the mid-line of the rising and falling curves at `points` outputs.
/// `vacuum` makes setpoints negative (jamming fingers). An invalid argument on a bad sweep.
host::Result<std::vector<protocol::InversePoint>> FitStaticInverse(
    const std::vector<SweepSample>& sweep, int points, bool vacuum);

/// The PlayModel a pi/api parameter set stands for (for residuals and charts).
PlayModel ModelOf(protocol::CompensatorKind kind, const std::vector<float>& params);

/// Writes kind and params into a finger's configuration; bad_value (the firmware's reason) when
/// they do not fit, the finger unchanged.
host::Outcome ApplyFit(const HysteresisFit& fit, protocol::ConfigureFinger& finger);

}  // namespace palpa::calibration
