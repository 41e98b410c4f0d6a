// Calibration files: writing the JSON schema, loading (checks in calibration_read.cc), atomic save.
#include "palpa/host/calibration_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "calibration_json.h"
#include "palpa/host/calibration_units.h"
#include "palpa/host/file_write.h"
#include "palpa/host/json_check.h"
#include "palpa/protocol/messages_stream.h"

namespace palpa::host {
namespace {

using nlohmann::json;
namespace pp = protocol;

json FitJson(const LineFit& f) {
  return {{"slope", f.slope}, {"intercept", f.intercept}, {"r2", f.r2}};
}

json Write(const CalibrationFile& c) {
  const bool jamming = c.kind == pp::FingerKind::kJamming;
  json j;
  j["schema"] = "palpa-calibration";
  j["schema_version"] = kCalibrationSchemaVersion;  // what it reads in is written as current
  j["actuator_serial"] = c.actuator_serial;
  j["kind"] = jamming ? "jamming" : "pneumatic";
  j["board_id"] = c.board_id;
  j["finger"] = c.finger;
  j["date"] = c.date;
  j["rig"] = c.rig;
  if (c.simulation) {
    j["simulation"] = {{"actuator_unit", c.simulation->actuator_unit},
                       {"seed", c.simulation->seed},
                       {"plant_level", c.simulation->plant_level},
                       {"effects", c.simulation->effects}};
  }
  j["conditions"] = {
      {"speed_um_s", c.speed_um_s}, {"depth_um", c.depth_um}, {"repeats", c.repeats}};
  if (c.bias_pa) j["conditions"]["bias_pa"] = *c.bias_pa;
  j["raw_data"] = c.raw_data;
  j["curve"] = json::array();
  for (const CurvePoint& p : c.curve)
    j["curve"].push_back({{"drive_pa", p.drive_pa}, {"output", p.output}});
  if (c.rising_fit || c.falling_fit) {
    j["fits"] = json::object();
    if (c.rising_fit) j["fits"]["rising"] = FitJson(*c.rising_fit);
    if (c.falling_fit) j["fits"]["falling"] = FitJson(*c.falling_fit);
  }
  if (!c.grid.empty()) {
    j["grid"] = json::array();
    for (const GridPoint& g : c.grid) {
      j["grid"].push_back({{"bias_pa", g.bias_pa},
                           {"vacuum_pa", g.vacuum_pa},
                           {"cycles", g.cycles},
                           {"stiffness_mean", g.stiffness_mean},
                           {"stiffness_spread", g.stiffness_spread},
                           {"loop_area_mean", g.loop_area_mean},
                           {"r2_min", g.r2_min}});
    }
  }
  j["static_inverse"] = json::array();
  for (const pp::InversePoint& p : c.static_inverse)
    j["static_inverse"].push_back({{"output", p.output}, {"setpoint_pa", p.setpoint_pa}});
  if (!c.regulator_corrections.empty()) {
    j["regulator_corrections"] = json::array();
    for (const RegulatorCorrection& rc : c.regulator_corrections) {
      json points = json::array();
      for (const pp::CorrectionPoint& p : rc.points) {
        points.push_back({{"command_pa", p.command_pa},
                          {"rising_pa", p.rising_pa},
                          {"falling_pa", p.falling_pa}});
      }
      j["regulator_corrections"].push_back({{"line", rc.line}, {"points", points}});
    }
  }
  if (!c.chamber_models.empty()) j["chamber_models"] = ChamberModelsJson(c);
  j["compensator"] = {
      {"kind", pp::EnumNames(pp::CompensatorKind{})[static_cast<size_t>(c.compensator)]},
      {"params", c.compensator_params}};
  if (c.recommended_bias_pa) j["recommended_bias_pa"] = *c.recommended_bias_pa;
  j["quality"] = {{"residual_rms", c.quality.residual_rms},
                  {"residual_max", c.quality.residual_max},
                  {"points", c.quality.points},
                  {"flags", c.quality.flags}};
  if (!c.quality.protocol.empty()) j["quality"]["protocol"] = c.quality.protocol;
  if (c.quality.cycles > 0) j["quality"]["cycles"] = c.quality.cycles;
  if (c.quality.rig_time_s > 0) j["quality"]["rig_time_s"] = c.quality.rig_time_s;
  if (c.quality.map_error) j["quality"]["map_error"] = *c.quality.map_error;
  if (!c.quality.checks.empty()) {
    j["quality"]["checks"] = json::array();
    for (const QualityCheck& k : c.quality.checks) {
      j["quality"]["checks"].push_back({{"name", k.name},
                                        {"value", k.value},
                                        {"limit", k.limit},
                                        {"unit", CheckUnit(k.name)},
                                        {"passed", k.passed},
                                        {"detail", k.detail}});
    }
  }
  return j;
}

}  // namespace

bool ValidSerial(const std::string& serial) {
  if (serial.empty() || serial.size() > 11) return false;
  for (char ch : serial) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-') return false;
  }
  return true;
}

std::string SimEffectsError(const std::string& effects) {
  size_t at = 0;
  while (!effects.empty() && at <= effects.size()) {
    const size_t comma = std::min(effects.find(',', at), effects.size());
    const std::string item = effects.substr(at, comma - at);
    if (item.rfind("history=", 0) == 0) {
      char* end = nullptr;
      const double h = std::strtod(item.c_str() + 8, &end);
      if (item.size() == 8 || *end != '\0' || !(h >= 0 && h <= 0.5))
        return "'" + item + "': history wants a fraction of 0 to 0.5";
    } else if (item != "creep" && item != "rate") {
      return "unknown effect '" + item + "' (expected creep, rate, history=FRACTION)";
    }
    at = comma + 1;
  }
  return {};
}

Result<CalibrationFile> ParseCalibration(const std::string& text) {
  const auto j = ParseJson(text);
  if (!j.ok()) return j.outcome();
  try {
    return CalibrationFromJson(j.value);
  } catch (const std::exception& e) {  // JsonInvalid names the field
    return {Status::kInvalidArgument, e.what()};
  }
}

Result<CalibrationFile> LoadCalibration(const std::string& path) {
  return ReadAndParse(path, kCalibrationFileLimits, ParseCalibration);
}

Result<std::string> SerializeCalibration(const CalibrationFile& c) {
  std::string text = Write(c).dump(2) + "\n";
  // What is written must read back: the same validation guards both directions.
  if (const auto back = ParseCalibration(text); !back.ok()) return back.outcome();
  return text;
}

Outcome SaveCalibration(const CalibrationFile& c, const std::string& path) {
  const auto text = SerializeCalibration(c);
  if (!text.ok()) return text.outcome();
  return WriteFileWhole(path, text.value);
}

std::string DefaultCalibrationDir() {
  if (const char* dir = std::getenv("PALPA_CALIBRATION_DIR"); dir != nullptr && *dir != '\0')
    return dir;
  if (const char* data = std::getenv("XDG_DATA_HOME"); data != nullptr && *data != '\0') {
    return std::string(data) + "/palpa/calibrations";
  }
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr ? home : ".") + "/.local/share/palpa/calibrations";
}

FingerCurves CurvesFromCalibration(const CalibrationFile& c) {
  FingerCurves curves;
  curves.source = "calibration of " + c.actuator_serial + " (" + c.date + ", " + c.rig + ")";
  // The stiffness map speaks kPa, mm and N/mm; the file the board's Pa, µm and mN/mm.
  for (const CurvePoint& p : c.curve)
    curves.calibrated.push_back({p.drive_pa / 1000, p.output / 1000});
  if (c.kind == pp::FingerKind::kJamming) {
    curves.stiffness_at_0 = c.curve.front().output / 1000;
    curves.stiffness_at_full_vacuum = c.curve.back().output / 1000;
  } else {
    curves.max_deformation_mm = c.curve.back().output / 1000;
  }
  return curves;
}

std::string CalibrationPath(const std::string& dir, const std::string& serial) {
  return dir + "/" + serial + ".json";
}

Result<CalibrationFile> FindCalibration(const std::string& dir, const std::string& serial) {
  if (!ValidSerial(serial)) {
    return {pp::Status::kNotFound,
            "actuator serial '" + serial + "' cannot name a calibration file"};
  }
  const std::string path = CalibrationPath(dir, serial);
  struct stat st;
  if (lstat(path.c_str(), &st) != 0)
    return {pp::Status::kNotFound, "no calibration for " + serial + " in " + dir};
  auto c = LoadCalibration(path);
  if (!c.ok()) return {pp::Status::kBadValue, c.message};
  if (c.value.actuator_serial != serial) {
    return {pp::Status::kBadValue,
            path + ": actuator_serial is " + c.value.actuator_serial + ", not " + serial};
  }
  return std::move(c.value);
}

std::string CompensatorLabel(const CalibrationFile& c) {
  const std::string kind(pp::EnumNames(pp::CompensatorKind{})[static_cast<size_t>(c.compensator)]);
  const auto& p = c.compensator_params;
  size_t n = 0;
  switch (c.compensator) {
    case pp::CompensatorKind::kPrandtlIshlinskii:  // offset, w0, n thresholds, n weights
      n = p.size() >= 2 ? (p.size() - 2) / 2 : 0;
      break;
    case pp::CompensatorKind::kAsymmetricPi:  // n first
      n = p.empty() ? 0 : static_cast<size_t>(p[0]);
      break;
    case pp::CompensatorKind::kBranch:  // band, dead band, then three values a point
      n = p.size() >= 2 ? (p.size() - 2) / 3 : 0;
      break;
    default:
      break;
  }
  return n > 0 ? kind + "(" + std::to_string(n) + ")" : kind;
}

}  // namespace palpa::host
