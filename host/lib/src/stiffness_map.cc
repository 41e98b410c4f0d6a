// Mapping of levels, 0..1, N/mm, mm and kPa onto a finger's output unit or raw setpoints.
#include "palpa/host/stiffness_map.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "number_text.h"
#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

using protocol::FingerKind;
using protocol::Status;

const char kShippedLevels[] =
#include "levels_json.inc"
    ;

Mapped Refuse(const std::string& why, Status status = Status::kOutOfRange) {
  Mapped m;
  m.status = status;
  m.error = why;
  return m;
}

/// Which range a curve-bound value is held to: a calibration's only when one is loaded, else
/// the nominal curve's, named with what it stands on (`nominal`).
std::string CurveRange(const FingerCurves& c, const char* nominal) {
  return c.calibrated.empty() ? nominal : "the calibrated range";
}

/// Keeps v in [lo, hi] under the policy (a clamp is added to *note); out of range when refused.
/// A value that is not a finite number has no place in any range: refused under every policy.
/// `range` names the range ("the calibrated range", "the range").
Outcome InRange(double& v, double lo, double hi, RangePolicy policy, const std::string& what,
                const std::string& range, std::string* note) {
  if (!std::isfinite(v))
    return Outcome::Fail(Status::kOutOfRange, what + " " + Num(v) + " is not a finite number");
  if (v >= lo && v <= hi) return {};
  if (policy == RangePolicy::kRefuse) {
    return Outcome::Fail(Status::kOutOfRange, what + " " + Num(v) + " is outside " + range + " " +
                                                  Num(lo) + " … " + Num(hi));
  }
  const double clamped = v < lo ? lo : hi;
  *note += "clamped " + what + " " + Num(v) + " to " + Num(clamped) + "; ";
  v = clamped;
  return {};
}

/// The calibrated curve at kpa (inside its range: callers check first).
double CalibratedAt(const FingerCurves& c, double kpa) {
  const auto& t = c.calibrated;
  const bool rising = t.back().first > t.front().first;
  for (size_t i = 1; i < t.size(); ++i) {
    const bool within = rising ? kpa <= t[i].first : kpa >= t[i].first;
    if (within || i + 1 == t.size()) {
      const double span = t[i].first - t[i - 1].first;
      const double f = span != 0 ? (kpa - t[i - 1].first) / span : 0;
      return t[i - 1].second + std::clamp(f, 0.0, 1.0) * (t[i].second - t[i - 1].second);
    }
  }
  return t.front().second;
}

double DeformationAt(const FingerCurves& c, double kpa) {
  if (!c.calibrated.empty()) return CalibratedAt(c, kpa);
  return std::max(0.0, c.deformation_slope_mm_per_kpa * kpa + c.deformation_intercept_mm);
}

double StiffnessAt(const FingerCurves& c, double vacuum_kpa) {
  if (!c.calibrated.empty()) return CalibratedAt(c, vacuum_kpa);
  return c.stiffness_at_0 + (c.stiffness_at_full_vacuum - c.stiffness_at_0) * (-vacuum_kpa / 100.0);
}

/// One table of levels: 1 to 32 pressures within [lo, hi] kPa.
std::vector<double> Levels(const JsonObject& o, double lo, double hi) {
  const nlohmann::json& list = o.List("levels_kpa", 1, 32);
  std::vector<double> levels;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = o.Item("levels_kpa", i);
    if (!list[i].is_number()) throw JsonInvalid(where + ": must be a number");
    const double v = list[i].get<double>();
    if (v < lo || v > hi)
      throw JsonInvalid(where + ": " + Num(v) + " is outside " + Num(lo) + " … " + Num(hi) +
                        " kPa");
    levels.push_back(v);
  }
  return levels;
}

Result<LevelTables> ParseTables(const nlohmann::json& j) {
  try {
    JsonObject o(j, "", {"comment", "pneumatic", "jamming"});
    LevelTables t;
    t.pneumatic_kpa = Levels(JsonObject(o.At("pneumatic"), "pneumatic", {"levels_kpa"}), 0, 100);
    JsonObject jam(o.At("jamming"), "jamming",
                   {"levels_kpa", "bias_kpa", "alternative_middle_kpa"});
    t.jamming_kpa = Levels(jam, -100, 0);
    t.jamming_bias_kpa = jam.Number("bias_kpa", 0, 100);
    if (jam.Has("alternative_middle_kpa"))
      t.jamming_alternative_middle_kpa = jam.Number("alternative_middle_kpa", -100, 0);
    return t;
  } catch (const std::exception& e) {  // JsonInvalid names the field
    return {Status::kInvalidArgument, e.what()};
  }
}

}  // namespace

LevelTables LevelTables::Shipped() {
  return ParseTables(nlohmann::json::parse(kShippedLevels)).value;
}

Result<LevelTables> LevelTables::Load(const std::string& path) {
  const auto j = ReadJsonFile(path, kLevelsFileLimits);
  if (!j.ok()) return j.outcome();
  auto tables = ParseTables(j.value);
  if (!tables.ok()) tables.message = path + ": " + tables.message;
  return tables;
}

Mapped MapRequest(const protocol::FingerSummary& finger, const LevelTables& levels,
                  const FingerCurves& curves, Request request, RangePolicy policy) {
  const bool jamming = finger.kind == FingerKind::kJamming;
  Mapped m;
  m.note = curves.source + "; ";
  double kpa = 0;
  bool from_pressure = false;
  switch (request.kind) {
    case TargetKind::kLevel: {
      const auto& table = jamming ? levels.jamming_kpa : levels.pneumatic_kpa;
      const double level = request.value;
      if (!std::isfinite(level)) return Refuse("level " + Num(level) + " is not a finite number");
      if (level != std::floor(level) || level < 0 || level >= static_cast<double>(table.size())) {
        return Refuse("level " + Num(level) + " does not exist: this finger has levels 0 … " +
                      std::to_string(table.size() - 1));
      }
      kpa = table[static_cast<size_t>(level)];
      from_pressure = true;
      m.from_table = true;
      m.table_kpa = kpa;
      break;
    }
    case TargetKind::kPressureKpa: {
      double v = request.value;
      if (jamming) {
        if (const Outcome r = InRange(v, -100, 0, policy, "vacuum (kPa)", "the range", &m.note);
            !r.ok())
          return Refuse(r.message);
        m.line_a_pa = static_cast<int32_t>(levels.jamming_bias_kpa * 1000);
        m.line_b_pa = static_cast<int32_t>(std::lround(v * 1000));
      } else {
        if (const Outcome r = InRange(v, 0, 100, policy, "pressure (kPa)", "the range", &m.note);
            !r.ok())
          return Refuse(r.message);
        m.line_a_pa = static_cast<int32_t>(std::lround(v * 1000));
      }
      m.raw = true;
      m.note = "raw setpoints, no compensation; ";
      return m;
    }
    case TargetKind::kStiffnessNPerMm: {
      if (!jamming) {
        return Refuse(
            "N/mm means nothing for a pneumatic finger: it renders deformation (use mm, a level or "
            "0..1)",
            Status::kBadValue);
      }
      double v = request.value;
      if (const Outcome r = InRange(v, curves.stiffness_at_0, curves.stiffness_at_full_vacuum,
                                    policy, "stiffness (N/mm)",
                                    CurveRange(curves,
                                               "the nominal curve's range (Fig 5-36(c)'s axis "
                                               "range, an assumption until the finger is "
                                               "calibrated)"),
                                    &m.note);
          !r.ok()) {
        return Refuse(r.message);
      }
      m.target = static_cast<int32_t>(std::lround(v * 1000));
      return m;
    }
    case TargetKind::kDeformationMm: {
      if (jamming) {
        return Refuse(
            "mm means nothing for a jamming finger: it renders stiffness (use N/mm, a level or "
            "0..1)",
            Status::kBadValue);
      }
      double v = request.value;
      if (const Outcome r =
              InRange(v, 0, curves.max_deformation_mm, policy, "deformation (mm)",
                      CurveRange(curves,
                                 "the nominal curve's range (Table 5-4's bare film, no top "
                                 "layer)"),
                      &m.note);
          !r.ok())
        return Refuse(r.message);
      m.target = static_cast<int32_t>(std::lround(v * 1000));
      return m;
    }
    case TargetKind::kNormalized: {
      double v = request.value;
      if (const Outcome r = InRange(v, 0, 1, policy, "normalised stiffness", "the range", &m.note);
          !r.ok())
        return Refuse(r.message);
      m.target = jamming
                     ? static_cast<int32_t>(std::lround(
                           1000 * (curves.stiffness_at_0 +
                                   v * (curves.stiffness_at_full_vacuum - curves.stiffness_at_0))))
                     : static_cast<int32_t>(std::lround(1000 * v * curves.max_deformation_mm));
      if (jamming && v == 0) m.target = 0;  // 0 is "off": released vacuum
      return m;
    }
  }
  if (from_pressure && !curves.calibrated.empty()) {
    // A calibrated curve covers what was measured, no more.
    const double a = curves.calibrated.front().first, b = curves.calibrated.back().first;
    if (const Outcome r = kpa != 0
                              ? InRange(kpa, std::min(a, b), std::max(a, b), policy,
                                        "level pressure (kPa)", "the calibrated range", &m.note)
                              : Outcome{};
        !r.ok()) {
      return Refuse(r.message);
    }
  }
  if (from_pressure) {
    // A level is a pressure or vacuum from the table, rendered through the finger's curve so the
    // compensator (not the table) decides the setpoint.
    if (jamming) {
      m.target = kpa == 0 ? 0 : static_cast<int32_t>(std::lround(1000 * StiffnessAt(curves, kpa)));
    } else {
      m.target =
          kpa == 0 ? 0 : static_cast<int32_t>(std::lround(1000 * DeformationAt(curves, kpa)));
    }
  }
  return m;
}

double StiffnessAtVacuum(const FingerCurves& curves, double vacuum_kpa) {
  if (!curves.calibrated.empty()) {
    const double a = curves.calibrated.front().first, b = curves.calibrated.back().first;
    vacuum_kpa = std::clamp(vacuum_kpa, std::min(a, b), std::max(a, b));
  }
  return StiffnessAt(curves, std::clamp(vacuum_kpa, -100.0, 0.0));
}

double DeformationAtPressure(const FingerCurves& curves, double kpa) {
  if (!curves.calibrated.empty()) {
    const double a = curves.calibrated.front().first, b = curves.calibrated.back().first;
    kpa = std::clamp(kpa, std::min(a, b), std::max(a, b));
  }
  return DeformationAt(curves, kpa);
}

double LinePressurePa(const protocol::LineSummary& line, const protocol::LineSample& sample) {
  return line.has_sensor ? sample.measured_pa : sample.setpoint_pa;
}

std::vector<double> EstimateFingerOutputs(const protocol::HelloReply& board,
                                          const std::vector<FingerCurves>& curves,
                                          const protocol::LineSample* tick) {
  std::vector<double> out;
  for (uint8_t f = 0; f < board.finger_count && f < curves.size(); ++f) {
    const protocol::FingerSummary& finger = board.fingers[f];
    if (finger.kind == FingerKind::kJamming) {
      const uint8_t line = finger.line_b != protocol::kNoLine ? finger.line_b : finger.line_a;
      const double kpa =
          line < board.line_count ? LinePressurePa(board.lines[line], tick[line]) / 1000.0 : 0.0;
      out.push_back(StiffnessAt(curves[f], std::clamp(kpa, -100.0, 0.0)));
    } else {
      const uint8_t line = finger.line_a;
      const double kpa =
          line < board.line_count ? LinePressurePa(board.lines[line], tick[line]) / 1000.0 : 0.0;
      out.push_back(DeformationAt(curves[f], std::clamp(kpa, 0.0, 100.0)));
    }
  }
  return out;
}

const char* OutputUnitName(protocol::FingerKind kind) {
  return kind == FingerKind::kJamming ? "N/mm" : "mm";
}

}  // namespace palpa::host
