// A calibration finds the actuator unit's own branches, not the nominal unit's: the quick protocol
// (palpa calibrate --quick) of simulated units 12 and 0 on the in-process rig (virtual time and
// seeded noise, so the comparison is the same on a loaded machine as on an idle one) differs as
// the two units truly do. The command line's half (the unit reaches palpa-sim, and the CLI says
// which one it calibrated) is CliCalibrateUnits.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "palpa/calibration/calibration_protocol.h"
#include "palpa/core/board_configs.h"
#include "palpa/hal/sim/plant.h"
#include "sim_rig.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;

namespace {

/// The true major branches of finger 1 (thesis-5finger) of `unit`, through the readings the
/// quick sweep takes on each branch within 10-90 kPa: least-squares slopes, rising and falling,
/// in mm/kPa (= µm/Pa, the calibration file's unit).
std::pair<double, double> TrueSlopes(uint32_t unit) {
  const auto& config = *palpa::core::FindBoardConfig("thesis-5finger");
  palpa::sim::PlantOptions o;
  o.unit = unit;
  palpa::sim::Plant plant(config.lines.data(), config.line_count, config.fingers.data(),
                          config.finger_count, o);
  const std::vector<double> kpa = {10, 20, 30, 40, 50, 60, 70, 80, 90};
  auto slope = [&](float (palpa::sim::PneumaticActuator::*branch)(float) const) {
    double sxy = 0, sxx = 0;
    for (double x : kpa) {
      sxy += (x - 50) * (plant.pneumatic(0)->*branch)(static_cast<float>(x));
      sxx += (x - 50) * (x - 50);
    }
    return sxy / sxx;
  };
  return {slope(&palpa::sim::PneumaticActuator::RisingMajorMm),
          slope(&palpa::sim::PneumaticActuator::FallingMajorMm)};
}

/// The quick protocol on finger 1 of simulated `unit` (seed 1, plant level 3: palpa calibrate
/// --rig sim --quick --unit N), the rig's stage stopping on its load cell as palpa-sim's does.
cal::CalibrationRun CalibrateUnit(uint32_t unit) {
  pt::SimRig sim({"thesis-5finger", 0, unit, 1});
  sim.force_stop = true;
  cal::Rig rig = sim.rig();
  cal::Journal journal;
  cal::CalibrationRun run;
  const cal::RunInfo info{"PN-1", 1, "2026-11-22T12:00:00Z", "sim", "PN-1.csv"};
  const cal::RigStatus s =
      cal::RunCalibration(rig, 0, cal::QuickProtocol(), info, journal, nullptr, &run);
  CHECK_TEXT(s.ok(), s.message.c_str());
  CHECK(run.file.rising_fit.has_value() && run.file.falling_fit.has_value());
  return run;
}

}  // namespace

TEST_GROUP(CalibrationUnits){};

TEST(CalibrationUnits, AQuickCalibrationOfUnit12FindsUnit12sOwnSlopes) {
  // Unit 12's slopes are about 10 % below unit 0's: the rig reads a slope within about 2 % (its
  // readings repeat to 2.82 %, five touches averaged), so a unit much closer to the nominal one
  // (unit 2, 3.5 %) would be told apart by the rig's scatter, not its own shape. The rig reads a
  // slope a few percent off the truth, as much as units 0 and 2 differ: unit 0 calibrated on the
  // same rig gives that offset, and the two calibrations must differ as the units do.
  const cal::CalibrationRun own = CalibrateUnit(12);
  const cal::CalibrationRun nominal = CalibrateUnit(0);
  const auto [own_rising, own_falling] = TrueSlopes(12);
  const auto [nominal_rising, nominal_falling] = TrueSlopes(0);
  CHECK_TEXT(std::fabs(own_rising - nominal_rising) > 0.01 * nominal_rising, "units differ");
  for (const bool rising : {true, false}) {
    const double truly = rising ? own_rising - nominal_rising : own_falling - nominal_falling;
    const double found = rising ? own.file.rising_fit->slope - nominal.file.rising_fit->slope
                                : own.file.falling_fit->slope - nominal.file.falling_fit->slope;
    CHECK_TEXT(std::fabs(found - truly) < 0.4 * std::fabs(truly),
               (std::string(rising ? "rising" : "falling") + ": units 12 and 0 calibrated " +
                std::to_string(found) + " apart, truly " + std::to_string(truly))
                   .c_str());
  }
}
