// Calibration documents from JSON: the schema's checks, each naming the field that fails.
#pragma once

#include <nlohmann/json.hpp>

#include "palpa/host/calibration_file.h"
#include "palpa/host/json_check.h"

namespace palpa::host {

/// Reads and checks a calibration document; throws JsonInvalid (json_check.h) naming the field.
CalibrationFile CalibrationFromJson(const nlohmann::json& root);

/// The chamber models of a version 3 document (calibration_chamber.cc), and their JSON.
void ReadChamberModels(JsonObject& o, CalibrationFile& c);
nlohmann::json ChamberModelsJson(const CalibrationFile& c);

/// A line with its chamber model applied: chamber_tau_us, the overdrive bound, no slew limit.
void ShapeLine(const ChamberModel& m, protocol::ConfigureLine& line);

}  // namespace palpa::host
