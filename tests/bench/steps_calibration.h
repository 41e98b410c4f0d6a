// Each benchmark unit calibrated as palpa calibrate would on its rig: the regulator's static
// correction and the chamber's step response for the lines the steps run on, on an in-process
// rig of the same unit (the same regulator, sensor and actuator draws as the steps' board).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "palpa/calibration/chamber_step.h"
#include "palpa/calibration/procedures.h"
#include "sim_rig.h"

namespace palpa::bench {

struct UnitCalibration {
  std::array<std::vector<protocol::CorrectionPoint>, protocol::kMaxLines> correction{};
  std::array<calibration::ChamberFit, protocol::kMaxLines> chamber{};
};

/// Calibrates fingers 0 (pneumatic, line 0) and 3 (jamming, vacuum line 5) of unit `seed`, once.
inline const UnitCalibration& CalibrationFor(uint32_t seed) {
  static std::map<uint32_t, UnitCalibration> known;
  const auto found = known.find(seed);
  if (found != known.end()) return found->second;
  UnitCalibration& u = known[seed];
  for (uint8_t finger : {0, 3}) {
    testing::SimRig sim({"thesis-5finger", finger, seed, seed});
    calibration::Rig rig = sim.rig();
    const uint8_t line = sim.driven_line(finger);
    calibration::RegulatorCorrection(rig, finger, line, 8, 3.0, &u.correction[line]);
    calibration::ContactOptions o;
    double zero = 0;
    calibration::ZeroOnVentedSurface(rig, finger, o, &zero);
    const calibration::ChamberStepOptions step = calibration::ChamberStepFor(sim.jamming(finger));
    calibration::ChamberStep measured;
    calibration::MeasureChamberStep(rig, finger, zero, o, step, &measured);
    u.chamber[line] = measured.fit;
  }
  return u;
}

}  // namespace palpa::bench
