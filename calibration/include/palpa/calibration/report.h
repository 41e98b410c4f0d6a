// The calibration report: one HTML page with SVG plots — the sweep with its fits (deformation
// branches against Table 5-4, or stiffness at the recommended bias), the regulator correction,
// the compensator's residuals, and for jamming fingers force–depth loops and stiffness against
// vacuum per bias.
#pragma once

#include <string>

#include "palpa/calibration/calibration_protocol.h"

namespace palpa::calibration {

std::string RenderReport(const CalibrationRun& run);

}  // namespace palpa::calibration
