// Device: each finger's curve from what its board holds, calibration files beside it, and
// calibrations uploaded (board_curves.h, calibration_file.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>

#include "calibration_json.h"
#include "palpa/host/board_curves.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/device.h"
#include "palpa/host/field_text.h"
#include "palpa/protocol/config_records.h"

namespace palpa::host {

void Device::AttachCalibrations() {
  if (calibrations_attached_) return;
  calibrations_attached_ = true;
  const std::string dir =
      options_.calibration_dir.empty() ? DefaultCalibrationDir() : options_.calibration_dir;
  for (uint8_t f = 0; f < curves_.size(); ++f) {
    std::string& note = calibration_notes_[f];
    note = FingerName(f) + ": ";
    if (!options_.use_calibrations) {
      note += "nominal curves (calibrations not used)";
      continue;
    }
    const auto finger = ReadFinger(f);
    if (!finger.ok()) {
      note += "nominal curves (configuration not readable: " + finger.message + ")";
      continue;
    }
    const std::string serial = FieldText(finger.value.actuator_serial);
    const auto c = FindCalibration(dir, serial);
    std::string error = c.message;
    if (c.ok() && c.value.kind != finger.value.kind) {
      error = CalibrationPath(dir, serial) + ": the calibration of " + serial +
              " is for another finger kind";
    } else if (c.ok()) {
      AttachCalibration(f, finger.value, c.value, CalibrationPath(dir, serial));
      continue;
    }
    // Every request through these curves says why they are not a calibration's.
    if (IsNominalInverse(finger.value)) {
      note += "nominal curves (" + error + ")";
      curves_[f].source = "nominal thesis curves (" + error + "; " + kNominalCurvesBasis + ")";
    } else {
      curves_[f] =
          CurvesFromBoard(finger.value, BoardCurveName(f, finger.value) + " (" + error + ")");
      note += curves_[f].source;
    }
    if (c.status != Status::kNotFound) calibration_problems_[f] = error;  // a file, unusable
  }
}

std::string Device::BoardCurveName(uint8_t finger, const pp::ConfigureFinger& f) const {
  return "the board's static inverse for " + FingerName(finger) + " (" +
         (IsNominalInverse(f) ? std::string("the nominal one")
                              : std::to_string(f.inverse_count) + " points") +
         ")";
}

void Device::AttachCalibration(uint8_t f, const pp::ConfigureFinger& board,
                               const CalibrationFile& file, const std::string& path) {
  const CurveComparison cmp = CompareWithBoard(file, board);
  const double tolerance = CurveTolerance(file);
  if (cmp.overlap && cmp.disagreement <= tolerance) {  // the board holds this calibration
    curves_[f] = CurvesFromBoard(board, CurvesFromCalibration(file).source);
    calibration_notes_[f] = FingerName(f) + ": " + curves_[f].source;
    return;
  }
  // The board maps targets through its own inverse whatever the file says: follow the board.
  CurveWarning w;
  w.finger = f;
  w.file = path;
  w.board = BoardCurveName(f, board);
  w.overlap = cmp.overlap;
  w.disagreement = cmp.disagreement;
  w.at_pa = cmp.at_pa;
  w.residual = tolerance;
  w.unit = file.kind == pp::FingerKind::kJamming ? "mN/mm" : "µm";
  char size[160];
  if (cmp.overlap) {
    std::snprintf(size, sizeof(size),
                  "by %.0f %s at %.1f kPa, more than the file's fit residual "
                  "(%.0f %s RMS)",
                  w.disagreement, w.unit.c_str(), w.at_pa / 1000, w.residual, w.unit.c_str());
  } else {
    std::snprintf(size, sizeof(size), "over every drive (the two curves share no pressure range)");
  }
  w.message = FingerName(f) + ": calibration file " + path + " disagrees with " + w.board + " " +
              size +
              "; requests follow the board's curve (apply the file to the finger to use "
              "it)";
  curves_[f] = CurvesFromBoard(board, w.board + "; " + path + " disagrees with it");
  if (IsNominalInverse(board)) curves_[f].source += "; " + std::string(kNominalCurvesBasis);
  calibration_notes_[f] = FingerName(f) + ": " + curves_[f].source;
  calibration_problems_[f] = w.message;
  curve_warnings_.push_back(std::move(w));
}

Outcome Device::ApplyCalibration(uint8_t finger, const CalibrationFile& c) {
  AttachCalibrations();  // so the lookup cannot later overwrite what this sets
  const auto current = ReadFinger(finger);
  if (!current.ok()) return Outcome{current.status, "apply calibration: " + current.message, {}};
  pp::ConfigureFinger f = current.value;
  const std::string serial = FieldText(f.actuator_serial);
  if (serial != c.actuator_serial) {
    return Outcome{Status::kBadValue,
                   "apply calibration: " + FingerName(finger) + " is actuator '" + serial +
                       "', the calibration is for '" + c.actuator_serial + "'",
                   {}};
  }
  const auto calibrated = CalibratedFinger(f, c);
  if (!calibrated.ok())
    return Outcome::Fail(calibrated.status, "apply calibration: " + calibrated.message);
  f = calibrated.value;
  // One staged blob: the board validates every record and applies all of them or none.
  std::vector<uint8_t> records;
  auto append = [&records](const auto& message) {
    uint8_t record[pp::kRecordHeaderSize + 512];
    const auto size = pp::EncodeRecord(message, record, sizeof(record));
    if (!size.ok()) return false;
    records.insert(records.end(), record, record + size.value);
    return true;
  };
  if (!append(f))
    return Outcome{Status::kBadValue, "apply calibration: the finger record cannot be encoded", {}};
  // Each of the finger's lines once, with its correction and its chamber model (step shaping).
  for (const uint8_t index : {f.line_a, f.line_b}) {
    if (index == pp::kNoLine) continue;
    const auto line = ReadLine(index);
    if (!line.ok()) return Outcome{line.status, "apply calibration: " + line.message, {}};
    pp::ConfigureLine l = line.value;
    const auto changed = CalibratedLine(c, index, l);
    if (!changed.ok())
      return Outcome::Fail(changed.status, "apply calibration: " + changed.message);
    if (!changed.value) continue;
    if (!append(l))
      return Outcome{Status::kBadValue, "apply calibration: the line record cannot be encoded", {}};
  }
  for (const RegulatorCorrection& rc : c.regulator_corrections) {
    if (rc.line != f.line_a && rc.line != f.line_b) {
      return Outcome{Status::kBadValue,
                     "apply calibration: a regulator correction is for " + LineName(rc.line) +
                         ", which is not one of this finger's",
                     {}};
    }
  }
  for (const ChamberModel& m : c.chamber_models) {
    if (m.line != f.line_a && m.line != f.line_b) {
      return Outcome{Status::kBadValue,
                     "apply calibration: a chamber model is for " + LineName(m.line) +
                         ", which is not one of this finger's",
                     {}};
    }
  }
  Outcome o = ConfigureStaged(records.data(), records.size());
  if (!o.ok()) {
    o.message = "apply calibration: " + o.message;
    return o;
  }
  // What the board now holds is what requests go through: the inverse just applied.
  curves_[finger] = CurvesFromBoard(f, CurvesFromCalibration(c).source);
  calibration_problems_[finger].clear();
  std::erase_if(curve_warnings_, [&](const CurveWarning& w) { return w.finger == finger; });
  calibration_notes_[finger] = FingerName(finger) + ": " + curves_[finger].source;
  if (const std::string note = ChamberNote(c); !note.empty())
    calibration_notes_[finger] += "; " + note;
  return o;
}

}  // namespace palpa::host
