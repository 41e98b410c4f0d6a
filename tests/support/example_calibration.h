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
  c.simulation = host::SimulatedPlant{2, 1, 3, "creep,rate"};
  c.speed_um_s = 100;
  c.depth_um = 0;
  c.repeats = 1;
  c.raw_data = "PN-1.csv";
  c.curve = {{0, 0}, {10000, 300}, {30000, 1200}, {60000, 2600}, {100000, 4200}};
  c.rising_fit = host::LineFit{0.0428, -250, 0.97};
  c.falling_fit = host::LineFit{0.0475, -50, 0.98};
  c.static_inverse = {{0, 0}, {300, 10000}, {1200, 30000}, {2600, 60000}, {4200, 100000}};
  c.regulator_corrections.push_back(
      host::RegulatorCorrection{0, {{0, 0, 0}, {50000, 50600, 49500}, {90000, 90800, 89700}}});
  c.chamber_models = {host::ChamberModel{0, 0.006, 0.02, 0.005, 0.012, 0.0035, 0.015}};
  c.compensator = pp::CompensatorKind::kPrandtlIshlinskii;
  c.compensator_params = {-200, 0.03f, 0, 25000, 0.01f, 0.005f};
  c.quality.residual_rms = 12;
  c.quality.residual_max = 40;
  c.quality.points = 120;
  c.quality.protocol = "adaptive";
  c.quality.cycles = 17;
  c.quality.rig_time_s = 1234.5;
  c.quality.map_error = 0.021;
  c.quality.checks = {{"points", 28, 8, true, "28 sweep readings"},
                      {"noise", 1.6, 5.1, true, "force noise 1.6 mN"},
                      {"force_zero", 0.4, 5.1, true, "readings stray up to 0.4 mN"},
                      {"leak", 1.7, 1, false, "line 2 holds 85 kPa at a 90 kPa command"},
                      {"previous", 0.4, 1, true, "differs by 1 %"}};
  return c;
}

/// A jamming finger's calibration with its grid and recommended bias (the parts a pneumatic one
/// has not), an api compensator.
inline host::CalibrationFile ExampleJammingCalibration() {
  namespace pp = palpa::protocol;
  host::CalibrationFile c = ExampleCalibration();
  c.actuator_serial = "JAM-1";
  c.kind = pp::FingerKind::kJamming;
  c.finger = 3;
  c.raw_data = "JAM-1.csv";
  c.speed_um_s = 100;
  c.depth_um = 3000;
  c.repeats = 8;
  c.bias_pa = 20000;
  c.curve = {{0, 700}, {-50000, 980}, {-100000, 1300}};
  c.rising_fit.reset();
  c.falling_fit.reset();
  c.grid = {{0, 0, 8, 690, 12, 0.41, 0.998},
            {20000, 0, 8, 702, 10, 0.20, 0.999},
            {20000, -100000, 8, 1296, 21, 0.11, 0.999}};
  c.static_inverse = {{700, 0}, {980, -50000}, {1300, -100000}};
  c.regulator_corrections = {
      host::RegulatorCorrection{3, {{2000, 2010, 1990}, {18000, 18050, 17950}}},
      host::RegulatorCorrection{4, {{-10000, -9900, -10100}, {-90000, -89500, -90300}}}};
  c.chamber_models = {host::ChamberModel{4, 0.003, 0.02, 0.047, 0.01, 0.03, 0.012}};
  c.compensator = pp::CompensatorKind::kAsymmetricPi;
  c.compensator_params = {2, 650, 0.004f, 10000, 30000, 0.001f, 0.0005f, 200, 0.3f};
  c.recommended_bias_pa = 20000;
  c.quality.residual_rms = 6;
  c.quality.residual_max = 15;
  return c;
}

}  // namespace palpa::testing
