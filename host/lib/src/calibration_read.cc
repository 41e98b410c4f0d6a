// Calibration documents from JSON, section by section, with the failing field named.
#include "calibration_json.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "palpa/core/compensator.h"
#include "palpa/host/calibration_units.h"
#include "palpa/host/json_check.h"
#include "palpa/protocol/messages_stream.h"

namespace palpa::host {
namespace {

using nlohmann::json;
namespace pp = protocol;

using Invalid = JsonInvalid;
using Obj = JsonObject;

/// What changed between the schema's versions: version 1 wrote pressures in kPa, deformation and
/// the conditions' lengths in mm, stiffness in N/mm and forces in N beside the board's Pa, µm and
/// mN/mm; version 2 writes the board's units throughout (calibration_units.h). Every changed
/// unit is a factor of 1000, and the fields whose unit is in their name were renamed with it.
/// Error messages name the file's own fields, in its own units.
struct Version {
  int number = kCalibrationSchemaVersion;
  bool v1() const { return number == 1; }
  double factor() const { return v1() ? 1000 : 1; }  ///< to the current unit
  const char* Key(const char* v1_key, const char* key) const { return v1() ? v1_key : key; }
  /// A number in the current unit, its range given in the current unit. A converted value is held
  /// to that range: it was accepted in the old unit and may only round across its edge.
  double Number(const Obj& o, const char* v1_key, const char* key, double lo, double hi) const {
    if (!v1()) return o.Number(key, lo, hi);
    return std::clamp(o.Number(v1_key, lo / factor(), hi / factor()) * factor(), lo, hi);
  }
  /// A number whose unit did not change.
  double Same(const Obj& o, const char* key, double lo, double hi) const {
    return o.Number(key, lo, hi);
  }
};

void CheckMonotone(const std::vector<double>& v, const std::string& path, int direction) {
  for (size_t i = 1; i < v.size(); ++i) {
    if (direction > 0 ? !(v[i] > v[i - 1]) : !(v[i] < v[i - 1])) {
      throw Invalid(path + "[" + std::to_string(i) + "]: not strictly " +
                    (direction > 0 ? "increasing" : "decreasing"));
    }
  }
}

/// A branch's line: output per Pa (mm/kPa in version 1: the same number) and its intercept.
LineFit ReadFit(const json& j, const std::string& path, const Version& v) {
  Obj o(j, path, {"slope", "intercept", "r2"});
  return LineFit{v.Same(o, "slope", -1e6, 1e6), v.Number(o, "intercept", "intercept", -1e9, 1e9),
                 v.Same(o, "r2", 0, 1)};
}

/// Schema, identity of the actuator and board, date and rig.
Version ReadIdentity(Obj& o, CalibrationFile& c) {
  if (o.Text("schema") != "palpa-calibration")
    throw Invalid("schema: must be \"palpa-calibration\"");
  c.schema_version = static_cast<int>(o.Integer("schema_version", 1, 1000));
  if (c.schema_version < 1 || c.schema_version > kCalibrationSchemaVersion) {
    throw Invalid("schema_version: " + std::to_string(c.schema_version) +
                  " is not a version this library reads (1 … " +
                  std::to_string(kCalibrationSchemaVersion) + ")");
  }
  c.actuator_serial = o.Text("actuator_serial");
  if (!ValidSerial(c.actuator_serial))
    throw Invalid("actuator_serial: 1-11 characters of A-Z a-z 0-9 _ -");
  const std::string kind = o.Text("kind");
  if (kind != "pneumatic" && kind != "jamming")
    throw Invalid("kind: must be \"pneumatic\" or \"jamming\"");
  c.kind = kind == "jamming" ? pp::FingerKind::kJamming : pp::FingerKind::kPneumatic;
  c.board_id = static_cast<uint32_t>(o.Integer("board_id", 0, 0xFFFFFFFFL));
  c.finger = static_cast<uint8_t>(o.Integer("finger", 0, pp::kMaxFingers - 1));
  c.date = o.Text("date");
  if (!std::regex_match(c.date, std::regex(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}Z)"))) {
    throw Invalid("date: must be UTC ISO 8601, e.g. 2026-11-22T12:00:00Z");
  }
  c.rig = o.Text("rig");
  return Version{c.schema_version};
}

/// The simulated plant of a calibration on palpa-sim's rig (version 2 on).
void ReadSimulation(Obj& o, CalibrationFile& c) {
  if (!o.Has("simulation")) return;
  Obj s(o.At("simulation"), "simulation", {"actuator_unit", "seed", "plant_level", "effects"});
  SimulatedPlant p;
  p.actuator_unit = static_cast<uint32_t>(s.Integer("actuator_unit", 0, 1000));
  p.seed = static_cast<uint32_t>(s.Integer("seed", 0, 0xFFFFFFFFL));
  p.plant_level = static_cast<int>(s.Integer("plant_level", 0, 3));
  const json& effects = s.At("effects");
  if (!effects.is_string()) throw Invalid("simulation.effects: must be a string");
  p.effects = effects.get<std::string>();
  if (const std::string why = SimEffectsError(p.effects); !why.empty())
    throw Invalid("simulation.effects: " + why);
  c.simulation = p;
}

/// Sweep conditions, the raw data's file name, the measured curve and its fits.
void ReadMeasurement(Obj& o, CalibrationFile& c, bool jamming, const Version& v) {
  const char* bias = v.Key("bias_kpa", "bias_pa");
  Obj k(o.At("conditions"), "conditions",
        {v.Key("speed_mm_s", "speed_um_s"), v.Key("depth_mm", "depth_um"), "repeats", bias});
  c.speed_um_s = v.Number(k, "speed_mm_s", "speed_um_s", 0.1, 10000);
  c.depth_um = v.Number(k, "depth_mm", "depth_um", 0, 20000);
  c.repeats = static_cast<int>(k.Integer("repeats", 0, 10000));
  if (k.Has(bias)) c.bias_pa = v.Number(k, "bias_kpa", "bias_pa", 0, 20000);
  if (jamming && !c.bias_pa) {
    throw Invalid(std::string("conditions.") + bias +
                  ": missing (a jamming curve depends on the bias)");
  }
  c.raw_data = o.Text("raw_data");
  if (c.raw_data.find("..") != std::string::npos || c.raw_data.front() == '/') {
    throw Invalid("raw_data: must name a file beside the calibration (no '..', not absolute)");
  }
  const json& list = o.List("curve", 2, 256);
  const char* drive_key = v.Key("kpa", "drive_pa");
  std::vector<double> drive, out;
  for (size_t i = 0; i < list.size(); ++i) {
    Obj p(list[i], o.Item("curve", i), {drive_key, "output"});
    drive.push_back(v.Number(p, "kpa", "drive_pa", jamming ? pp::kMinPressurePa : 0,
                             jamming ? 0 : pp::kMaxPressurePa));
    out.push_back(v.Number(p, "output", "output", 0, 1e6));
    c.curve.push_back({drive.back(), out.back()});
  }
  CheckMonotone(drive, std::string("curve.") + drive_key, jamming ? -1 : 1);
  CheckMonotone(out, "curve.output", 1);
  if (o.Has("fits")) {
    Obj f(o.At("fits"), "fits", {"rising", "falling"});
    if (f.Has("rising")) c.rising_fit = ReadFit(f.At("rising"), "fits.rising", v);
    if (f.Has("falling")) c.falling_fit = ReadFit(f.At("falling"), "fits.falling", v);
  }
}

/// The jamming grid of bias × vacuum levels, when the procedure measured one.
void ReadGrid(Obj& o, CalibrationFile& c, const Version& v) {
  if (!o.Has("grid")) return;
  const json& list = o.List("grid", 0, 1024);
  for (size_t i = 0; i < list.size(); ++i) {
    Obj g(list[i], o.Item("grid", i),
          {v.Key("bias_kpa", "bias_pa"), v.Key("vacuum_kpa", "vacuum_pa"), "cycles",
           "stiffness_mean", "stiffness_spread", "loop_area_mean", "r2_min"});
    GridPoint p;
    p.bias_pa = v.Number(g, "bias_kpa", "bias_pa", 0, 20000);
    p.vacuum_pa = v.Number(g, "vacuum_kpa", "vacuum_pa", pp::kMinPressurePa, 0);
    p.cycles = static_cast<int>(g.Integer("cycles", 1, 10000));
    p.stiffness_mean = v.Number(g, "stiffness_mean", "stiffness_mean", 0, 1e6);
    p.stiffness_spread = v.Number(g, "stiffness_spread", "stiffness_spread", 0, 1e6);
    p.loop_area_mean = v.Same(g, "loop_area_mean", 0, 1e6);
    p.r2_min = v.Same(g, "r2_min", 0, 1);
    c.grid.push_back(p);
  }
}

/// The finger's static inverse: output unit → setpoint, both monotone.
void ReadStaticInverse(Obj& o, CalibrationFile& c, bool jamming) {
  const json& list = o.List("static_inverse", 2, pp::kMaxInversePoints);
  std::vector<double> outputs, setpoints;
  for (size_t i = 0; i < list.size(); ++i) {
    Obj p(list[i], o.Item("static_inverse", i), {"output", "setpoint_pa"});
    pp::InversePoint q;
    q.output = static_cast<int32_t>(p.Integer("output", 0, pp::kMaxFingerTarget));
    q.setpoint_pa = static_cast<int32_t>(p.Integer("setpoint_pa", jamming ? pp::kMinPressurePa : 0,
                                                   jamming ? 0 : pp::kMaxPressurePa));
    outputs.push_back(q.output);
    setpoints.push_back(q.setpoint_pa);
    c.static_inverse.push_back(q);
  }
  CheckMonotone(outputs, "static_inverse.output", 1);
  CheckMonotone(setpoints, "static_inverse.setpoint_pa", jamming ? -1 : 1);
}

/// Each line's regulator curve (command → rising and falling pressure), one entry per line.
void ReadRegulatorCorrections(Obj& o, CalibrationFile& c) {
  if (!o.Has("regulator_corrections")) return;
  const json& list = o.List("regulator_corrections", 0, 2);
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string where = o.Item("regulator_corrections", k);
    Obj r(list[k], where, {"line", "points"});
    RegulatorCorrection rc;
    rc.line = static_cast<uint8_t>(r.Integer("line", 0, pp::kMaxLines - 1));
    for (const RegulatorCorrection& other : c.regulator_corrections) {
      if (other.line == rc.line)
        throw Invalid(where + ".line: line " + std::to_string(rc.line) + " appears twice");
    }
    const json& points = r.List("points", 2, pp::kMaxCorrectionPoints);
    std::vector<double> command, rising, falling;
    for (size_t i = 0; i < points.size(); ++i) {
      Obj p(points[i], r.Item("points", i), {"command_pa", "rising_pa", "falling_pa"});
      pp::CorrectionPoint q;
      q.command_pa =
          static_cast<int32_t>(p.Integer("command_pa", pp::kMinPressurePa, pp::kMaxPressurePa));
      q.rising_pa =
          static_cast<int32_t>(p.Integer("rising_pa", pp::kMinPressurePa, pp::kMaxPressurePa));
      q.falling_pa =
          static_cast<int32_t>(p.Integer("falling_pa", pp::kMinPressurePa, pp::kMaxPressurePa));
      command.push_back(q.command_pa);
      rising.push_back(q.rising_pa);
      falling.push_back(q.falling_pa);
      rc.points.push_back(q);
    }
    const int direction = command.back() > command.front() ? 1 : -1;
    CheckMonotone(command, where + ".points.command_pa", direction);
    CheckMonotone(rising, where + ".points.rising_pa", direction);
    CheckMonotone(falling, where + ".points.falling_pa", direction);
    c.regulator_corrections.push_back(rc);
  }
}

/// The compensator, checked by the board's own rules so a file the board would Nack is refused.
void ReadCompensator(Obj& o, CalibrationFile& c) {
  Obj k(o.At("compensator"), "compensator", {"kind", "params"});
  const std::string name = k.Text("kind");
  const auto names = pp::EnumNames(pp::CompensatorKind{});
  size_t index = 0;
  const size_t count = static_cast<size_t>(pp::CompensatorKind::kCount);
  while (index < count && name != names[index]) ++index;
  if (index >= count) throw Invalid("compensator.kind: unknown \"" + name + "\"");
  c.compensator = static_cast<pp::CompensatorKind>(index);
  const json& list = k.List("params", 0, pp::kMaxCompensatorParams);
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_number() || !std::isfinite(list[i].get<double>())) {
      throw Invalid(k.Item("params", i) + ": must be a finite number");
    }
    c.compensator_params.push_back(list[i].get<float>());
  }
  pp::ConfigureFinger f{};
  f.compensator = c.compensator;
  f.param_count = static_cast<uint8_t>(c.compensator_params.size());
  std::copy(c.compensator_params.begin(), c.compensator_params.end(), f.params.begin());
  if (const char* why = core::CompensatorParamsError(f))
    throw Invalid(std::string("compensator.params: ") + why);
}

/// Residuals, flags, and the run's figures and detector verdicts (optional: older files load).
void ReadQuality(Obj& o, CalibrationFile& c, const Version& v) {
  Obj q(o.At("quality"), "quality",
        {"residual_rms", "residual_max", "points", "flags", "protocol", "cycles", "rig_time_s",
         "map_error", "checks"});
  c.quality.residual_rms = v.Number(q, "residual_rms", "residual_rms", 0, 1e9);
  c.quality.residual_max = v.Number(q, "residual_max", "residual_max", 0, 1e9);
  c.quality.points = static_cast<int>(q.Integer("points", 0, 10000000));
  const json& flags = q.List("flags", 0, 64);
  for (size_t i = 0; i < flags.size(); ++i) {
    if (!flags[i].is_string()) throw Invalid(q.Item("flags", i) + ": must be a string");
    c.quality.flags.push_back(flags[i].get<std::string>());
  }
  if (q.Has("protocol")) c.quality.protocol = q.Choice("protocol", {"thesis", "adaptive"});
  if (q.Has("cycles")) c.quality.cycles = static_cast<int>(q.Integer("cycles", 0, 100000));
  if (q.Has("rig_time_s")) c.quality.rig_time_s = q.Number("rig_time_s", 0, 1e7);
  if (q.Has("map_error")) c.quality.map_error = q.Number("map_error", 0, 100);
  if (!q.Has("checks")) return;
  const json& checks = q.List("checks", 0, 16);
  for (size_t i = 0; i < checks.size(); ++i) {
    const std::string where = q.Item("checks", i);
    Obj k(checks[i], where,
          v.v1() ? std::set<std::string>{"name", "value", "limit", "passed", "detail"}
                 : std::set<std::string>{"name", "value", "limit", "unit", "passed", "detail"});
    QualityCheck check;
    check.name = k.Choice("name", {"points", "noise", "force_zero", "leak", "previous"});
    const std::string unit = CheckUnit(check.name);
    if (!v.v1() && k.Text("unit") != unit)
      throw Invalid(where + ".unit: a " + check.name + " check is in " + unit);
    // Version 1 gave the force checks in N; their unit is now mN like every force of the file.
    const bool force = unit == "mN";
    check.value =
        force ? v.Number(k, "value", "value", -1e12, 1e12) : v.Same(k, "value", -1e12, 1e12);
    check.limit =
        force ? v.Number(k, "limit", "limit", -1e12, 1e12) : v.Same(k, "limit", -1e12, 1e12);
    check.passed = k.Flag("passed");
    check.detail = k.Text("detail");
    c.quality.checks.push_back(check);
  }
}

}  // namespace

CalibrationFile CalibrationFromJson(const json& root) {
  Obj o(root, "",
        {"schema",
         "schema_version",
         "actuator_serial",
         "kind",
         "board_id",
         "finger",
         "date",
         "rig",
         "simulation",
         "conditions",
         "raw_data",
         "curve",
         "fits",
         "grid",
         "static_inverse",
         "regulator_corrections",
         "chamber_models",
         "compensator",
         "recommended_bias_kpa",
         "recommended_bias_pa",
         "quality"});
  CalibrationFile c;
  const Version v = ReadIdentity(o, c);
  // The fields the other versions have.
  std::vector<const char*> others =
      v.v1() ? std::vector<const char*>{"simulation", "recommended_bias_pa"}
             : std::vector<const char*>{"recommended_bias_kpa"};
  if (v.number < 3) others.push_back("chamber_models");
  for (const char* other : others) {
    if (root.contains(other)) {
      throw Invalid(std::string(other) + ": unknown field in schema version " +
                    std::to_string(v.number));
    }
  }
  const char* recommended = v.Key("recommended_bias_kpa", "recommended_bias_pa");
  const bool jamming = c.kind == pp::FingerKind::kJamming;
  ReadSimulation(o, c);
  ReadMeasurement(o, c, jamming, v);
  ReadGrid(o, c, v);
  ReadStaticInverse(o, c, jamming);
  ReadRegulatorCorrections(o, c);
  ReadChamberModels(o, c);
  ReadCompensator(o, c);
  if (o.Has(recommended))
    c.recommended_bias_pa = v.Number(o, "recommended_bias_kpa", "recommended_bias_pa", 0, 20000);
  ReadQuality(o, c, v);
  return c;
}

}  // namespace palpa::host
