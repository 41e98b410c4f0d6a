// The calibration file's unit table: one unit per quantity, the board's.
#include "palpa/host/calibration_units.h"

#include <cmath>

namespace palpa::host {
namespace {

namespace pp = protocol;

constexpr const char* kDeformation = "µm";
constexpr const char* kStiffness = "mN/mm";

const char* Output(pp::FingerKind kind) {
  return kind == pp::FingerKind::kJamming ? kStiffness : kDeformation;
}

// A constant table, not a function-local vector: nothing is allocated on first use.
constexpr CalibrationField kFields[] = {
    {"schema_version", "version", "version", "version of this schema"},
    {"board_id", "id", "id", "the board's identity (Hello)"},
    {"finger", "index", "index", "the finger, from 0"},
    {"simulation.actuator_unit", "index", "index", "palpa-sim's actuator unit (0 nominal)"},
    {"simulation.seed", "id", "id", "palpa-sim's regulator, sensor and noise seed"},
    {"simulation.plant_level", "index", "index", "palpa-sim's plant level, 0-3"},
    {"conditions.speed_um_s", "µm/s", "µm/s", "indentation speed"},
    {"conditions.depth_um", "µm", "µm", "indentation depth (jamming presses)"},
    {"conditions.repeats", "count", "count", "presses per condition"},
    {"conditions.bias_pa", "Pa", "Pa", "bias the curve was taken at"},
    {"curve[].drive_pa", "Pa", "Pa", "drive: pressure, or vacuum (negative)"},
    {"curve[].output", kDeformation, kStiffness, "output on the branches' mid-line"},
    {"fits.rising.slope", "µm/Pa", "mN/mm/Pa", "rising branch, 10-90 % (µm/Pa = mm/kPa)"},
    {"fits.rising.intercept", kDeformation, kStiffness, "rising branch at 0 Pa"},
    {"fits.rising.r2", "1", "1", "coefficient of determination"},
    {"fits.falling.slope", "µm/Pa", "mN/mm/Pa", "falling branch, 10-90 %"},
    {"fits.falling.intercept", kDeformation, kStiffness, "falling branch at 0 Pa"},
    {"fits.falling.r2", "1", "1", "coefficient of determination"},
    {"grid[].bias_pa", "Pa", "Pa", "condition's bias"},
    {"grid[].vacuum_pa", "Pa", "Pa", "condition's vacuum (negative)"},
    {"grid[].cycles", "count", "count", "presses at the condition"},
    {"grid[].stiffness_mean", kStiffness, kStiffness, "mean contact stiffness"},
    {"grid[].stiffness_spread", kStiffness, kStiffness, "its standard deviation"},
    {"grid[].loop_area_mean", "mJ", "mJ", "mean press loop area"},
    {"grid[].r2_min", "1", "1", "worst press fit's R²"},
    {"static_inverse[].output", kDeformation, kStiffness, "target"},
    {"static_inverse[].setpoint_pa", "Pa", "Pa", "drive for it"},
    {"regulator_corrections[].line", "index", "index", "the board's line, from 0"},
    {"regulator_corrections[].points[].command_pa", "Pa", "Pa", "command, trim off"},
    {"regulator_corrections[].points[].rising_pa", "Pa", "Pa", "measured, commands rising"},
    {"regulator_corrections[].points[].falling_pa", "Pa", "Pa", "measured, commands falling"},
    {"chamber_models[].line", "index", "index", "the board's line, from 0"},
    {"chamber_models[].dead_time_s", "s", "s", "step response: dead time"},
    {"chamber_models[].regulator_tau_s", "s", "s", "the regulator's lag the fit assumed"},
    {"chamber_models[].chamber_tau_s", "s", "s", "the chamber's lag behind it"},
    {"chamber_models[].fit_rms", "1", "1", "fit residual, a fraction of the step"},
    {"chamber_models[].tube_tau_s", "s", "s", "lag behind the outlet, tube's law (v4)"},
    {"chamber_models[].tube_fit_rms", "1", "1", "its fit residual, a fraction of the step"},
    {"recommended_bias_pa", "Pa", "Pa", "least loop area keeping the range"},
    {"quality.residual_rms", kDeformation, kStiffness, "compensator's fit residual, RMS"},
    {"quality.residual_max", kDeformation, kStiffness, "and largest"},
    {"quality.points", "count", "count", "sweep readings the fits used"},
    {"quality.cycles", "count", "count", "indentation cycles of the map"},
    {"quality.rig_time_s", "s", "s", "rig time of the whole run"},
    {"quality.map_error", "1", "1", "cross-validated map error, relative"},
};

}  // namespace

std::span<const CalibrationField> CalibrationFields() { return kFields; }

std::string CalibrationFieldUnit(const std::string& path, pp::FingerKind kind) {
  for (const auto& f : CalibrationFields()) {
    if (path == f.path) return kind == pp::FingerKind::kJamming ? f.jamming : f.pneumatic;
  }
  return {};
}

std::string CheckUnit(const std::string& name) {
  if (name == "points") return "count";
  if (name == "noise" || name == "force_zero") return "mN";
  if (name == "leak" || name == "previous") return "1";
  return {};
}

std::vector<std::string> CompensatorParamUnits(pp::CompensatorKind kind,
                                               const std::vector<float>& params,
                                               pp::FingerKind finger) {
  const std::string out = Output(finger), per_pa = out + "/Pa";
  std::vector<std::string> units;
  auto repeat = [&](size_t n, const std::string& unit) { units.insert(units.end(), n, unit); };
  switch (kind) {
    case pp::CompensatorKind::kPrandtlIshlinskii: {  // offset, w0, r1..rn, w1..wn
      if (params.size() < 2 || params.size() % 2 != 0) return {};
      const size_t n = (params.size() - 2) / 2;
      units = {out, per_pa};
      repeat(n, "Pa");
      repeat(n, per_pa);
      break;
    }
    case pp::CompensatorKind::kAsymmetricPi: {  // n, offset, w0, r.., w.., d.., g..
      if (params.empty() || !std::isfinite(params[0]) || params[0] < 0) return {};
      const size_t n = static_cast<size_t>(params[0]);
      if (params.size() < 3 + 2 * n || (params.size() - 3 - 2 * n) % 2 != 0) return {};
      const size_t zones = (params.size() - 3 - 2 * n) / 2;
      units = {"count", out, per_pa};
      repeat(n, "Pa");
      repeat(n, per_pa);
      repeat(zones, out);  // knots of S, which maps w0·u + Σ w z (output units) to the output
      repeat(zones, "1");
      break;
    }
    case pp::CompensatorKind::kBranch: {  // band, dead band, y1..K, rising 1..K, falling 1..K
      if (params.size() < 2 || (params.size() - 2) % 3 != 0) return {};
      const size_t k = (params.size() - 2) / 3;
      units = {out, "Pa"};
      repeat(k, out);
      repeat(2 * k, "Pa");
      break;
    }
    default:
      if (!params.empty()) return {};
      break;
  }
  return units;
}

}  // namespace palpa::host
