// Calibration documents from JSON: the schema's checks, each naming the field that fails.
#pragma once

#include <nlohmann/json.hpp>

#include "palpa/host/calibration_file.h"

namespace palpa::host {

/// Reads and checks a calibration document; throws JsonInvalid (json_check.h) naming the field.
CalibrationFile CalibrationFromJson(const nlohmann::json& root);

}  // namespace palpa::host
