// The calibration file's chamber models: read with their checks, written, noted when absent, and
// what applying a calibration does to its finger's and lines' records (step shaping on).
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "calibration_json.h"

namespace palpa::host {

namespace pp = protocol;

void ReadChamberModels(JsonObject& o, CalibrationFile& c) {
  if (!o.Has("chamber_models")) return;
  const nlohmann::json& list = o.List("chamber_models", 0, 2);
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string where = o.Item("chamber_models", k);
    // The tube's lag is version 4's: a file of version 3 holds only the lag behind the regulator
    // model, which the board no longer shapes with (docs/calibration.md, "Schema versions").
    const bool tube = c.schema_version >= 4;
    JsonObject m(
        list[k], where,
        tube ? std::set<std::string>{"line", "dead_time_s", "regulator_tau_s", "chamber_tau_s",
                                     "fit_rms", "tube_tau_s", "tube_fit_rms"}
             : std::set<std::string>{"line", "dead_time_s", "regulator_tau_s", "chamber_tau_s",
                                     "fit_rms"});
    ChamberModel model;
    model.line = static_cast<uint8_t>(m.Integer("line", 0, pp::kMaxLines - 1));
    for (const ChamberModel& other : c.chamber_models) {
      if (other.line == model.line)
        throw JsonInvalid(where + ".line: line " + std::to_string(model.line) + " appears twice");
    }
    model.dead_time_s = m.Number("dead_time_s", 0, 1);
    model.regulator_tau_s = m.Number("regulator_tau_s", 0, 10);
    // 0 would mean no model (the board would not shape): a file that says 0 says nothing.
    model.chamber_tau_s = m.Number("chamber_tau_s", 1e-6, 10);
    model.fit_rms = m.Number("fit_rms", 0, 1);
    // Absent in a version 4 file rewritten from an older one: known in the old sense only.
    if (tube && (m.Has("tube_tau_s") || m.Has("tube_fit_rms"))) {  // both or neither
      model.tube_tau_s = m.Number("tube_tau_s", 1e-6, 10);
      model.tube_fit_rms = m.Number("tube_fit_rms", 0, 1);
    }
    c.chamber_models.push_back(model);
  }
}

nlohmann::json ChamberModelsJson(const CalibrationFile& c) {
  nlohmann::json list = nlohmann::json::array();
  for (const ChamberModel& m : c.chamber_models) {
    nlohmann::json j = {{"line", m.line},
                        {"dead_time_s", m.dead_time_s},
                        {"regulator_tau_s", m.regulator_tau_s},
                        {"chamber_tau_s", m.chamber_tau_s},
                        {"fit_rms", m.fit_rms}};
    if (m.tube_tau_s > 0) j["tube_tau_s"] = m.tube_tau_s, j["tube_fit_rms"] = m.tube_fit_rms;
    list.push_back(j);
  }
  return list;
}

std::string ChamberNote(const CalibrationFile& c) {
  for (const ChamberModel& m : c.chamber_models) {
    if (m.tube_tau_s <= 0) {
      return "the chamber model of line " + std::to_string(m.line) +
             " is a lag behind the regulator (schema version " +
             std::to_string(std::min(c.schema_version, 3)) +
             "), not the tube's the board shapes with: steps are not shaped until the finger is "
             "calibrated again";
    }
  }
  if (!c.chamber_models.empty()) return "";
  if (c.schema_version < 3) {
    return "schema version " + std::to_string(c.schema_version) +
           " has no chamber model: steps are not shaped until the finger is calibrated again";
  }
  return "no chamber model: steps are not shaped";
}

void ShapeLine(const ChamberModel& m, pp::ConfigureLine& line) {
  // The board reads chamber_tau_us as the chamber's lag behind the outlet through the tube's law
  // (firmware.md): the tube's lag, never the one behind the regulator model (ReadChamberModels).
  line.chamber_tau_us = static_cast<uint32_t>(std::max(1L, std::lround(1e6 * m.tube_tau_s)));
  line.overdrive_pa = kShapingOverdrivePa;
  // The overdrive bounds a shaped step; a slew limit would only slow it (docs/firmware.md).
  line.slew_pa_per_s = 0;
}

Result<pp::ConfigureFinger> CalibratedFinger(pp::ConfigureFinger f, const CalibrationFile& c) {
  if (f.kind != c.kind)
    return Outcome::Fail(Status::kBadValue, "the finger's kind differs from the calibration's");
  // A file read from disk is checked against these bounds; one built in memory may not be.
  if (c.static_inverse.size() > f.inverse.size())
    return Outcome::Fail(Status::kBadValue, "the calibration's static inverse has " +
                                                std::to_string(c.static_inverse.size()) +
                                                " points, a finger holds " +
                                                std::to_string(f.inverse.size()));
  if (c.compensator_params.size() > f.params.size())
    return Outcome::Fail(Status::kBadValue, "the calibration's compensator has " +
                                                std::to_string(c.compensator_params.size()) +
                                                " parameters, a finger holds " +
                                                std::to_string(f.params.size()));
  f.inverse_count = static_cast<uint8_t>(c.static_inverse.size());
  std::copy(c.static_inverse.begin(), c.static_inverse.end(), f.inverse.begin());
  f.compensator = c.compensator;
  f.param_count = static_cast<uint8_t>(c.compensator_params.size());
  std::copy(c.compensator_params.begin(), c.compensator_params.end(), f.params.begin());
  if (c.recommended_bias_pa && f.kind == pp::FingerKind::kJamming)
    f.bias_pa = static_cast<int32_t>(std::lround(*c.recommended_bias_pa));
  return f;
}

Result<bool> CalibratedLine(const CalibrationFile& c, uint8_t index, pp::ConfigureLine& line) {
  const auto rc = std::find_if(c.regulator_corrections.begin(), c.regulator_corrections.end(),
                               [index](const RegulatorCorrection& r) { return r.line == index; });
  // A model without the tube's lag (an older file's) is none for the board (ShapeLine).
  const auto chamber =
      std::find_if(c.chamber_models.begin(), c.chamber_models.end(),
                   [index](const ChamberModel& m) { return m.line == index && m.tube_tau_s > 0; });
  if (rc == c.regulator_corrections.end() && chamber == c.chamber_models.end()) return false;
  if (rc != c.regulator_corrections.end() && rc->points.size() > line.correction.size())
    return Outcome::Fail(Status::kBadValue, "line " + std::to_string(index) + "'s correction has " +
                                                std::to_string(rc->points.size()) +
                                                " points, a line holds " +
                                                std::to_string(line.correction.size()));
  if (rc != c.regulator_corrections.end()) {
    line.correction_count = static_cast<uint8_t>(rc->points.size());
    std::copy(rc->points.begin(), rc->points.end(), line.correction.begin());
  }
  if (chamber != c.chamber_models.end()) ShapeLine(*chamber, line);
  return true;
}

}  // namespace palpa::host
