// A calibration as the calibrate command writes one, with every optional part present: the
// reference the calibration file tests and the host files fuzzer start from.
#pragma once

#include "palpa/host/calibration_file.h"

namespace palpa::testing {

inline host::CalibrationFile ExampleCalibration() {
  namespace pp = palpa::protocol;
  host::CalibrationFile c;
  c.actuator_serial = "PN-1";
  c.kind = pp::FingerKind::kPneumatic;
  c.board_id = 1;
  c.finger = 0;
  c.date = "2026-11-22T12:00:00Z";
  c.rig = "sim";
  c.repeats = 1;
  c.raw_data = "PN-1.csv";
  c.curve = {{0, 0}, {10, 0.3}, {30, 1.2}, {60, 2.6}, {100, 4.2}};
  c.rising_fit = host::LineFit{0.0428, -0.25, 0.97};
  c.falling_fit = host::LineFit{0.0475, -0.05, 0.98};
  c.static_inverse = {{0, 0}, {300, 10000}, {1200, 30000}, {2600, 60000}, {4200, 100000}};
  c.regulator_corrections.push_back(
      host::RegulatorCorrection{0, {{0, 0, 0}, {50000, 50600, 49500}, {90000, 90800, 89700}}});
  c.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  c.compensator_params = {-200, 0.03f, 0, 25000, 0.01f, 0.005f};
  c.quality.residual_rms = 12;
  c.quality.residual_max = 40;
  c.quality.points = 120;
  c.quality.protocol = "adaptive";
  c.quality.cycles = 17;
  c.quality.rig_time_s = 1234.5;
  c.quality.map_error = 0.021;
  c.quality.checks = {{"noise", 0.0016, 0.0051, true, "force noise 1.6 mN"},
                      {"leak", 1.7, 1, false, "line 2 holds 85 kPa at a 90 kPa command"}};
  return c;
}

}  // namespace palpa::testing
