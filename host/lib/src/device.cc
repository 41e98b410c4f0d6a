// Device: fingers in people's terms on top of the link.
#include "palpa/host/device.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <type_traits>

#include "palpa/host/calibration_file.h"
#include "palpa/protocol/crc32.h"

namespace palpa::host {

Device::Device(std::unique_ptr<Link> link, DeviceOptions options)
    : link_(std::move(link)), options_(std::move(options)) {
  const pp::HelloReply b = link_->board();
  for (uint8_t f = 0; f < b.finger_count; ++f) modes_.push_back(b.fingers[f].mode);
  curves_.resize(b.finger_count);
  calibration_notes_.resize(b.finger_count);
}

void Device::AttachCalibrations() {
  if (calibrations_attached_) return;
  calibrations_attached_ = true;
  const std::string dir =
      options_.calibration_dir.empty() ? DefaultCalibrationDir() : options_.calibration_dir;
  for (uint8_t f = 0; f < curves_.size(); ++f) {
    std::string& note = calibration_notes_[f];
    note = "finger " + std::to_string(f + 1) + ": ";
    if (!options_.use_calibrations) {
      note += "nominal curves (calibrations not used)";
      continue;
    }
    std::string error;
    const auto finger = ReadFinger(f, &error);
    if (!finger.ok()) {
      note += "nominal curves (configuration not readable: " + error + ")";
      continue;
    }
    const std::string serial(
        finger.value.actuator_serial.data(),
        strnlen(finger.value.actuator_serial.data(), finger.value.actuator_serial.size()));
    const auto c = FindCalibration(dir, serial, &error);
    if (!c) {
      note += "nominal curves (" + error + ")";
      continue;
    }
    if (c->kind != finger.value.kind) {
      note += "nominal curves (the calibration of " + serial + " is for another finger kind)";
      continue;
    }
    curves_[f] = CurvesFromCalibration(*c);
    note += curves_[f].source;
  }
}

Outcome Device::ApplyCalibration(uint8_t finger, const CalibrationFile& c) {
  AttachCalibrations();  // so the lookup cannot later overwrite what this sets
  std::string error;
  const auto current = ReadFinger(finger, &error);
  if (!current.ok()) return Outcome{current.status, "apply calibration: " + error, {}};
  pp::ConfigureFinger f = current.value;
  const std::string serial(f.actuator_serial.data(),
                           strnlen(f.actuator_serial.data(), f.actuator_serial.size()));
  if (serial != c.actuator_serial) {
    return Outcome{Status::kBadValue,
                   "apply calibration: finger " + std::to_string(finger + 1) + " is actuator '" +
                       serial + "', the calibration is for '" + c.actuator_serial + "'",
                   {}};
  }
  if (f.kind != c.kind)
    return Outcome{Status::kBadValue,
                   "apply calibration: the finger's kind differs from the calibration's",
                   {}};
  f.inverse_count = static_cast<uint8_t>(c.static_inverse.size());
  std::copy(c.static_inverse.begin(), c.static_inverse.end(), f.inverse.begin());
  f.compensator = c.compensator;
  f.param_count = static_cast<uint8_t>(c.compensator_params.size());
  std::copy(c.compensator_params.begin(), c.compensator_params.end(), f.params.begin());
  if (c.recommended_bias_kpa && f.kind == pp::FingerKind::kJamming) {
    f.bias_pa = static_cast<int32_t>(std::lround(*c.recommended_bias_kpa * 1000));
  }
  // One staged blob: the board validates every record and applies all of them or none.
  std::vector<uint8_t> records;
  auto append = [&records](const auto& message) {
    uint8_t body[512];
    const auto size = pp::EncodeBody(message, body, sizeof(body));
    if (!size.ok()) return false;
    records.push_back(static_cast<uint8_t>(size.value));
    records.push_back(static_cast<uint8_t>(size.value >> 8));
    records.push_back(static_cast<uint8_t>(std::decay_t<decltype(message)>::kInfo.type));
    records.insert(records.end(), body, body + size.value);
    return true;
  };
  if (!append(f))
    return Outcome{Status::kBadValue, "apply calibration: the finger record cannot be encoded", {}};
  for (const RegulatorCorrection& rc : c.regulator_corrections) {
    if (rc.line != f.line_a && rc.line != f.line_b) {
      return Outcome{Status::kBadValue,
                     "apply calibration: a regulator correction is for line " +
                         std::to_string(rc.line + 1) + ", which is not one of this finger's",
                     {}};
    }
    const auto line = ReadLine(rc.line, &error);
    if (!line.ok()) return Outcome{line.status, "apply calibration: " + error, {}};
    pp::ConfigureLine l = line.value;
    l.correction_count = static_cast<uint8_t>(rc.points.size());
    std::copy(rc.points.begin(), rc.points.end(), l.correction.begin());
    if (!append(l))
      return Outcome{Status::kBadValue, "apply calibration: the line record cannot be encoded", {}};
  }
  Outcome o = ConfigureStaged(records.data(), records.size());
  if (!o.ok()) {
    o.message = "apply calibration: " + o.message;
    return o;
  }
  curves_[finger] = CurvesFromCalibration(c);
  calibration_notes_[finger] =
      "finger " + std::to_string(finger + 1) + ": " + curves_[finger].source;
  return o;
}

Device::~Device() { StopRecording(); }

Result<std::unique_ptr<Device>> Device::Attach(std::unique_ptr<Transport> transport,
                                               DeviceOptions options, std::string* error) {
  auto link = Link::Open(std::move(transport), options.link, error);
  if (!link.ok()) return link.status;
  return std::unique_ptr<Device>(new Device(std::move(link.value), std::move(options)));
}

Result<std::unique_ptr<Device>> Device::Open(const std::string& uri, DeviceOptions options,
                                             std::string* error) {
  auto transport = OpenTransport(uri, error);
  if (!transport.ok()) return transport.status;
  return Attach(std::move(transport.value), std::move(options), error);
}

Outcome Device::FromCommand(const CommandResult& r, const char* what) {
  Outcome o;
  o.status = r.status;
  if (r.status != Status::kOk) {
    o.message = std::string(what) + ": " + pp::StatusName(r.status) +
                (r.message.empty() ? "" : " — " + r.message);
    if (r.status == Status::kConditionPersists)
      o.message += " (the fault's cause is still present)";
  }
  return o;
}

Outcome Device::EnsureMode(uint8_t finger, pp::FingerMode mode) {
  if (finger >= modes_.size())
    return Outcome{
        Status::kNotFound, "finger " + std::to_string(finger + 1) + " does not exist", {}};
  if (modes_[finger] == mode) return {};
  const Outcome o = FromCommand(link_->Command(pp::SetFingerMode{finger, mode}), "set finger mode");
  if (o.ok()) modes_[finger] = mode;
  return o;
}

Outcome Device::Set(const std::vector<FingerRequest>& requests, bool wait) {
  AttachCalibrations();  // the curves requests are mapped through
  const pp::HelloReply b = link_->board();
  pp::SetFingerTargets targets{};
  pp::SetLineSetpoints lines{};
  Outcome out;
  // Map everything first: a bad request anywhere means nothing at all is sent.
  std::vector<Mapped> mapped;
  for (const FingerRequest& r : requests) {
    if (r.finger >= b.finger_count) {
      return Outcome{Status::kNotFound,
                     "finger " + std::to_string(r.finger + 1) + " does not exist (this board has " +
                         std::to_string(b.finger_count) + ")",
                     {}};
    }
    mapped.push_back(MapRequest(b.fingers[r.finger], options_.levels, curves_[r.finger], r.request,
                                options_.range_policy));
    if (mapped.back().status != Status::kOk) {
      return Outcome{mapped.back().status,
                     "finger " + std::to_string(r.finger + 1) + ": " + mapped.back().error,
                     {}};
    }
  }
  for (size_t i = 0; i < requests.size(); ++i) {
    const FingerRequest& r = requests[i];
    const Mapped& m = mapped[i];
    out.notes.push_back("finger " + std::to_string(r.finger + 1) + ": " + m.note);
    if (m.raw) {
      const Outcome mode = EnsureMode(r.finger, pp::FingerMode::kRaw);
      if (!mode.ok()) return mode;
      lines.entries[lines.entry_count++] =
          pp::LineSetpoint{b.fingers[r.finger].line_a, m.line_a_pa};
      if (b.fingers[r.finger].line_b != pp::kNoLine) {
        lines.entries[lines.entry_count++] =
            pp::LineSetpoint{b.fingers[r.finger].line_b, m.line_b_pa};
      }
    } else {
      const Outcome mode = EnsureMode(r.finger, pp::FingerMode::kTarget);
      if (!mode.ok()) return mode;
      targets.entries[targets.entry_count++] =
          pp::FingerTarget{r.finger,
                           b.fingers[r.finger].kind == pp::FingerKind::kJamming
                               ? pp::OutputUnit::kStiffnessMilliNewtonPerMm
                               : pp::OutputUnit::kDeformationMicrometre,
                           m.target};
    }
  }
  const int timeout = options_.link.command_timeout_ms;
  if (targets.entry_count > 0) {
    const uint32_t g = link_->StreamTargets(targets);
    const Status s = wait ? link_->WaitTargetsApplied(g, timeout) : Status::kOk;
    if (s != Status::kOk)
      return Outcome{s, std::string("the board did not apply the targets: ") + pp::StatusName(s),
                     out.notes};
  }
  if (lines.entry_count > 0) {
    const uint32_t g = link_->StreamSetpoints(lines);
    const Status s = wait ? link_->WaitSetpointsApplied(g, timeout) : Status::kOk;
    if (s != Status::kOk)
      return Outcome{s, std::string("the board did not apply the setpoints: ") + pp::StatusName(s),
                     out.notes};
  }
  return out;
}

Outcome Device::SetLines(const std::vector<std::pair<uint8_t, double>>& kpa, bool wait) {
  const pp::HelloReply b = link_->board();
  pp::SetLineSetpoints lines{};
  for (const auto& [line, value] : kpa) {
    if (line >= b.line_count)
      return Outcome{Status::kNotFound, "line " + std::to_string(line + 1) + " does not exist", {}};
    const double pa = value * 1000;
    if (pa < b.lines[line].limit_min_pa || pa > b.lines[line].limit_max_pa) {
      char text[160];
      std::snprintf(text, sizeof(text), "line %u: %g kPa is outside its limits %g … %g kPa",
                    line + 1u, value, b.lines[line].limit_min_pa / 1000.0,
                    b.lines[line].limit_max_pa / 1000.0);
      return Outcome{Status::kOutOfRange, text, {}};
    }
  }
  for (const auto& [line, value] : kpa) {  // all valid: only now does anything go out
    const double pa = value * 1000;
    for (uint8_t f = 0; f < b.finger_count; ++f) {
      if (b.fingers[f].line_a == line || b.fingers[f].line_b == line) {
        const Outcome mode = EnsureMode(f, pp::FingerMode::kRaw);
        if (!mode.ok()) return mode;
      }
    }
    lines.entries[lines.entry_count++] = pp::LineSetpoint{line, static_cast<int32_t>(pa)};
  }
  const uint32_t g = link_->StreamSetpoints(lines);
  const Status s =
      wait ? link_->WaitSetpointsApplied(g, options_.link.command_timeout_ms) : Status::kOk;
  if (s != Status::kOk)
    return Outcome{
        s, std::string("the board did not apply the setpoints: ") + pp::StatusName(s), {}};
  return {};
}

Outcome Device::EStop() {
  const Status s = link_->EStop();
  return s == Status::kOk ? Outcome{} : Outcome{s, "the board did not acknowledge the EStop", {}};
}

Outcome Device::ClearFault(uint32_t mask) {
  // The board keeps its outputs safe after clearing until new setpoints arrive.
  return FromCommand(link_->Command(pp::ClearFault{mask}), "clear fault");
}

Outcome Device::ConfigureLine(const pp::ConfigureLine& line) {
  return FromCommand(link_->Command(line), "configure line");
}
Outcome Device::ConfigureBoard(const pp::ConfigureBoard& board) {
  return FromCommand(link_->Command(board), "configure board");
}
Outcome Device::SaveConfig() {
  return FromCommand(link_->Command(pp::SaveConfig{}), "save configuration");
}
Outcome Device::FactoryReset() {
  Outcome o = FromCommand(link_->Command(pp::FactoryReset{}), "factory reset");
  if (!o.ok()) return o;
  // The factory configuration has its own host-silence timeout: heartbeats must follow it.
  std::string error;
  const auto board = ReadBoard(&error);
  if (board.ok()) {
    link_->SetHostTimeout(board.value.host_timeout_us);
  } else {
    o.notes.push_back("could not read back the host-silence timeout (" + error +
                      "): heartbeats keep their period until the next session");
  }
  return o;
}

Outcome Device::ConfigureFinger(const pp::ConfigureFinger& finger) {
  uint8_t body[512];
  const auto size = pp::EncodeBody(finger, body + 3, sizeof(body) - 3);
  if (!size.ok()) return Outcome{size.status, "configure finger: cannot encode", {}};
  if (size.value <= pp::kMaxBodySize)
    return FromCommand(link_->Command(finger), "configure finger");
  body[0] = static_cast<uint8_t>(size.value);
  body[1] = static_cast<uint8_t>(size.value >> 8);
  body[2] = static_cast<uint8_t>(pp::MessageType::kConfigureFinger);
  return ConfigureStaged(body, size.value + 3);
}

Outcome Device::ConfigureStaged(const uint8_t* records, size_t size) {
  if (size == 0 || size > pp::kMaxStagedBytes) {
    return Outcome{Status::kBadLength,
                   "staged configuration: " + std::to_string(size) + " bytes (1 to " +
                       std::to_string(pp::kMaxStagedBytes) + " fit the board's staging buffer)",
                   {}};
  }
  Outcome o =
      FromCommand(link_->Command(pp::StagedBegin{static_cast<uint16_t>(size)}), "staged begin");
  for (size_t at = 0; o.ok() && at < size; at += pp::kMaxStagedChunk) {
    pp::StagedPart part{};
    part.offset = static_cast<uint16_t>(at);
    part.data_size =
        static_cast<uint8_t>(size - at < pp::kMaxStagedChunk ? size - at : pp::kMaxStagedChunk);
    std::copy(records + at, records + at + part.data_size, part.data.begin());
    o = FromCommand(link_->Command(part), "staged part");
  }
  if (!o.ok()) return o;
  const CommandResult r =
      link_->Command(pp::StagedCommit{static_cast<uint16_t>(size), pp::Crc32(records, size)});
  o = FromCommand(r, "staged commit");
  // A record the board refused comes back as its section and index (ConfigError::detail()).
  const bool record_refused = r.status == Status::kBadLength || r.status == Status::kOutOfRange ||
                              r.status == Status::kBadValue || r.status == Status::kUnsupported;
  const uint32_t section = r.detail >> 8;
  if (record_refused && section < static_cast<uint32_t>(pp::ConfigSection::kCount)) {
    o.message += " (" + std::string(pp::EnumNames(pp::ConfigSection{})[section]) + " " +
                 std::to_string((r.detail & 0xFFu) + 1) + ")";
  }
  return o;
}

template <class M>
Result<M> Device::ReadSection(pp::ConfigSection section, uint8_t index, std::string* error) {
  std::vector<uint8_t> body;
  for (uint16_t offset = 0;;) {
    const CommandResult r = link_->Command(pp::GetConfig{section, index, offset});
    pp::ConfigReport report{};
    if (r.status != Status::kOk || !r.Reply(report)) {
      if (error != nullptr)
        *error = std::string("read configuration: ") + pp::StatusName(r.status) + " " + r.message;
      return r.status == Status::kOk ? Status::kBadValue : r.status;
    }
    body.insert(body.end(), report.data.begin(), report.data.begin() + report.data_size);
    offset = static_cast<uint16_t>(offset + report.data_size);
    if (offset >= report.total_bytes || report.data_size == 0) break;
  }
  M m{};
  pp::FieldError field;
  const Status s = pp::DecodeBody(body.data(), body.size(), m, &field);
  if (s != Status::kOk) {
    if (error != nullptr)
      *error = std::string("the board's configuration does not decode at ") +
               (field.field ? field.field : "?");
    return s;
  }
  return m;
}

Result<pp::ConfigureLine> Device::ReadLine(uint8_t line, std::string* error) {
  return ReadSection<pp::ConfigureLine>(pp::ConfigSection::kLine, line, error);
}
Result<pp::ConfigureFinger> Device::ReadFinger(uint8_t finger, std::string* error) {
  return ReadSection<pp::ConfigureFinger>(pp::ConfigSection::kFinger, finger, error);
}
Result<pp::ConfigureBoard> Device::ReadBoard(std::string* error) {
  return ReadSection<pp::ConfigureBoard>(pp::ConfigSection::kBoard, 0, error);
}

Result<pp::Diagnostics> Device::Diagnostics(std::string* error) {
  const CommandResult r = link_->Command(pp::GetDiagnostics{});
  pp::Diagnostics d{};
  if (r.status == Status::kOk && r.Reply(d)) return d;
  if (error != nullptr)
    *error = std::string("diagnostics: ") + pp::StatusName(r.status) + " " + r.message;
  return r.status == Status::kOk ? Status::kBadValue : r.status;
}

Result<pp::LoopStats> Device::LoopStats(std::string* error) {
  const CommandResult r = link_->Command(pp::GetLoopStats{});
  pp::LoopStats s{};
  if (r.status == Status::kOk && r.Reply(s)) return s;
  if (error != nullptr)
    *error = std::string("loop statistics: ") + pp::StatusName(r.status) + " " + r.message;
  return r.status == Status::kOk ? Status::kBadValue : r.status;
}

}  // namespace palpa::host
