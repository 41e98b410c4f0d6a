// A session's start: the board checked against the study before anything is set, the output
// directory claimed (or a session in it resumed), and the provenance every record carries.
#include "study_session.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "number_text.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/field_text.h"
#include "palpa/host/file_read.h"
#include "palpa/host/scene_predict.h"
#include "palpa/protocol/sha256.h"
#include "recording_format.h"

#ifndef PALPA_VERSION_TEXT
#define PALPA_VERSION_TEXT "unknown"
#endif

namespace palpa::host {
namespace {

std::string Hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof(b), "0x%08x", v);
  return b;
}

std::string Sha256Hex(const std::string& bytes) {
  protocol::Sha256Hasher h;
  h.Update(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  std::string out;
  for (uint8_t b : h.Finish()) {
    char x[3];
    std::snprintf(x, sizeof(x), "%02x", b);
    out += x;
  }
  return out;
}

/// The drive (kPa, magnitude) a value needs on finger f, or why the finger cannot show it.
Result<double> DriveKpa(Device& device, const Study& study, uint8_t f, double value) {
  const protocol::FingerSummary finger = device.info().fingers[f];
  const Mapped m =
      MapRequest(finger, device.levels(), device.curves(f), StudyRequest(study, value));
  if (m.status != Status::kOk)
    return {Status::kOutOfRange,
            device.FingerName(f) + ": " + Num(value) + " " + study.unit + ": " + m.error};
  if (m.raw) return std::max(std::abs(m.line_a_pa), std::abs(m.line_b_pa)) / 1000.0;
  if (m.from_table) return std::abs(m.table_kpa);
  return std::abs(DriveForOutput(finger.kind, device.curves(f), m.target / 1000.0));
}

}  // namespace

std::string UtcNow() {
  return recording::UtcText(
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
}

std::vector<double> StudyValues(const Study& study) {
  std::vector<double> values;
  for (const StudyCondition& c : study.conditions)
    values.insert(values.end(), c.values.begin(), c.values.end());
  for (const StudyBlock& b : study.blocks) {
    if (b.kind == BlockKind::kStaircase) {
      values.push_back(b.staircase.reference);
      values.push_back(b.staircase.start);
    }
  }
  return values;
}

double ResetValue(const Study& study) {
  const std::vector<double> v = StudyValues(study);
  if (study.approach_from_above) {
    return LargerIsStiffer(study) ? *std::max_element(v.begin(), v.end())
                                  : *std::min_element(v.begin(), v.end());
  }
  // Vented: 0 in every unit but stiffness, whose softest a finger can show is its own curve's.
  return study.unit == "N/mm" ? *std::min_element(v.begin(), v.end()) : 0.0;
}

Outcome CheckBoardForStudy(Device& device, const Study& study) {
  const protocol::HelloReply& info = device.info();
  const std::string board = FieldText(info.config_name);
  const char* kind = study.finger_kind == protocol::FingerKind::kJamming ? "jamming" : "pneumatic";
  if (info.finger_count < study.fingers) {
    return Outcome::Fail(Status::kUnsupported, "study " + study.name + " needs " +
                                                   std::to_string(study.fingers) + " " + kind +
                                                   " fingers; this " + board + " board has " +
                                                   std::to_string(info.finger_count));
  }
  for (uint8_t f = 0; f < study.fingers; ++f) {
    if (info.fingers[f].kind != study.finger_kind)
      return Outcome::Fail(Status::kUnsupported, device.FingerName(f) + " of this " + board +
                                                     " board is not a " + kind + " finger");
  }
  if (study.finger_kind == protocol::FingerKind::kJamming &&
      device.levels().jamming_bias_kpa != study.bias_kpa) {
    return Outcome::Fail(Status::kInvalidArgument,
                         "study " + study.name + " holds the bias at " + Num(study.bias_kpa) +
                             " kPa; the device maps jamming requests with a bias of " +
                             Num(device.levels().jamming_bias_kpa) + " kPa");
  }
  for (double v : StudyValues(study)) {
    for (uint8_t f = 0; f < study.fingers; ++f) {
      const Result<double> drive = DriveKpa(device, study, f, v);
      if (!drive.ok()) return drive.outcome();
      if (drive.value > study.cap_kpa + 1e-9) {
        return Outcome::Fail(Status::kOutOfRange, device.FingerName(f) + ": " + Num(v) + " " +
                                                      study.unit + " needs " + Num(drive.value) +
                                                      " kPa, beyond the study's cap of " +
                                                      Num(study.cap_kpa) + " kPa");
      }
    }
  }
  return {};
}

Result<std::vector<SettleLine>> StudyLines(Device& device, const Study& study,
                                           nlohmann::ordered_json* settle) {
  std::vector<SettleLine> lines;
  *settle = nlohmann::ordered_json::object();
  for (uint8_t f = 0; f < study.fingers; ++f) {
    const protocol::FingerSummary finger = device.info().fingers[f];
    for (const uint8_t l : std::array<uint8_t, 2>{finger.line_a, finger.line_b}) {
      if (l == protocol::kNoLine) continue;
      const auto line = device.ReadLine(l);
      if (!line.ok()) return line.outcome();
      const double tau = line.value.chamber_tau_us * 1e-6;
      lines.push_back({l, tau, line.value.kind});
      (*settle)[device.LineName(l)] =
          tau > 0 ? nlohmann::ordered_json(Num(tau) + " s tube lag behind the outlet")
                  : nlohmann::ordered_json("no chamber model: the outlet alone");
    }
  }
  return lines;
}

Result<StudyProvenance> Provenance(Device& device, const Study& study,
                                   const StudyRunOptions& options) {
  const protocol::HelloReply info = device.info();
  StudyProvenance p;
  p.palpa_version = PALPA_VERSION_TEXT;
  p.firmware_version = std::to_string(info.firmware_major) + "." +
                       std::to_string(info.firmware_minor) + "." +
                       std::to_string(info.firmware_patch);
  p.catalog_hash = Hex32(info.catalog_hash);
  const auto config = device.ReadConfig();
  if (!config.ok()) return config.outcome();
  p.config_crc = Hex32(core::ConfigCrc(config.value));
  const std::string dir =
      options.calibration_dir.empty() ? DefaultCalibrationDir() : options.calibration_dir;
  for (uint8_t f = 0; f < study.fingers && options.use_calibrations; ++f) {
    const auto finger = device.ReadFinger(f);
    if (!finger.ok()) return finger.outcome();
    const std::string path = CalibrationPath(dir, FieldText(finger.value.actuator_serial));
    const auto bytes = ReadFileWhole(path, kCalibrationFileLimits);
    if (bytes.ok()) p.calibration_files[path] = Sha256Hex(bytes.value);
  }
  p.board = options.board.empty() ? FieldText(info.config_name) : options.board;
  p.sim = options.sim;
  p.extra["config_name"] = FieldText(info.config_name);
  p.extra["curves"] = device.calibration_notes();
  return p;
}

}  // namespace palpa::host
