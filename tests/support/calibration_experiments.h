// Calibration experiments on the in-process simulated rig: a map scored against the simulated
// unit's truth (never seen by the protocols), and one run per failure detector with its fault
// injected or clean. Used by the calibration benchmark (many seeds) and the tests (one each).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "palpa/calibration/calibration_protocol.h"
#include "sim_rig.h"

namespace palpa::testing {

inline constexpr uint8_t kJammingFinger = 3;  ///< of thesis-5finger
inline constexpr uint8_t kPneumaticFinger = 0;

/// Held-out error of a map against the unit's static stiffness (rising from rest, as the map is
/// taken), over a 2.5 kPa × 2.5 kPa lattice of the box: relative to the true value.
struct MapScore {
  double rms = 0;
  double max = 0;
};
MapScore ScoreSurface(const std::vector<calibration::MapPress>& presses, SimRig& sim,
                      const calibration::MapBox& box = {});
/// The thesis's own reading of a grid: bilinear between the condition means.
MapScore ScoreBilinear(const std::vector<calibration::ConditionSummary>& grid, SimRig& sim,
                       const calibration::MapBox& box = {});

/// A whole calibration, short: quick settings and an adaptive map of 8 to 10 cycles.
calibration::ProtocolOptions ShortAdaptiveProtocol();

enum class Detector { kPoints, kNoise, kForceZero, kLeak, kPrevious };
std::vector<Detector> AllDetectors();
const char* DetectorName(Detector d);  ///< as the check is named in the file

struct DetectorCase {
  bool ran = false;  ///< the calibration finished (a safety stop is a failed case)
  std::string error;
  bool fired = false;      ///< this detector's check failed
  bool any_other = false;  ///< some other check failed too
  double value = 0, limit = 0;
  std::string detail;
  std::vector<std::string> flags;  ///< every flag of the calibration, for a reader to see why
};

/// One short calibration with the detector's fault injected (`inject`) or clean; the size of an
/// injected fault is drawn from its range by the seed. The previous-calibration detector first
/// calibrates the unit clean, then again (new seed) changed or unchanged.
DetectorCase RunDetectorCase(Detector d, bool inject, uint32_t seed);

}  // namespace palpa::testing
