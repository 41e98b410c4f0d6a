// Device: fingers in people's terms on top of the link (configuring the board: device_config.cc).
#include "palpa/host/device.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "palpa/hal/linux/atomic_file.h"
#include "palpa/host/device_uri.h"
#include "palpa/host/fault_text.h"
#include "palpa/host/field_text.h"
#include "palpa/protocol/config_records.h"

namespace palpa::host {

Device::Device(std::unique_ptr<Link> link, DeviceOptions options)
    : link_(std::move(link)), options_(std::move(options)) {
  const pp::HelloReply b = link_->board();
  for (uint8_t f = 0; f < b.finger_count; ++f) modes_.push_back(b.fingers[f].mode);
  curves_.resize(b.finger_count);
  calibration_notes_.resize(b.finger_count);
  calibration_problems_.resize(b.finger_count);
}

Device::~Device() { Close(); }

Outcome Device::Close() {
  StopRecording();
  const Status s = link_->Close();
  if (s == Status::kOk) return {};
  if (s == Status::kCatalogMismatch) {
    return Outcome{s,
                   "close: the board runs other firmware, so no Close was sent; it ends the "
                   "session by its host-silence timeout (nothing was actuated)",
                   {}};
  }
  return Outcome{s,
                 "close: the board did not answer the Close; it ends the session by its "
                 "host-silence timeout instead (safe either way)",
                 {}};
}

Outcome Device::Release() {
  const Status s = link_->Release();
  if (s == Status::kOk) return {};
  return Outcome{s,
                 std::string("release: ") + pp::StatusName(s) +
                     (s == Status::kNoSession ? " (" + link_->session_end() + ")" : ""),
                 {}};
}

std::string Device::FingerName(uint8_t finger) const {
  return "finger " + std::to_string(finger + options_.number_from);
}

std::string Device::LineName(uint8_t line) const {
  return "line " + std::to_string(line + options_.number_from);
}

Result<std::unique_ptr<Device>> Device::Attach(std::unique_ptr<Transport> transport,
                                               DeviceOptions options) {
  auto link = Link::Open(std::move(transport), options.link);
  if (!link.ok()) return link.outcome();
  return std::unique_ptr<Device>(new Device(std::move(link.value), std::move(options)));
}

Result<std::unique_ptr<Device>> Device::Open(const std::string& uri, DeviceOptions options,
                                             std::string* sim_truth_address) {
  auto transport = OpenTransport(uri, sim_truth_address);
  if (!transport.ok()) return transport.outcome();
  // A board on USB can be unplugged and plugged back in: the link opens it again by its URI.
  // A simulator child or a TCP server that went away is another board when it comes back.
  const DeviceUri parsed = ParseDeviceUri(uri).value;
  const bool pluggable = parsed.kind == DeviceUri::Kind::kUsb ||
                         parsed.kind == DeviceUri::Kind::kHid ||
                         parsed.kind == DeviceUri::Kind::kSerial;
  if (pluggable && options.link.reconnect && !options.link.reopen) {
    options.link.reopen = [uri] { return OpenTransport(uri); };
  }
  return Attach(std::move(transport.value), std::move(options));
}

std::string Device::FaultText(uint32_t bitmap, bool persist) {
  const auto diagnostics = Diagnostics();
  const std::string faults =
      DescribeFaults(bitmap, diagnostics.ok() ? &diagnostics.value : nullptr);
  const bool several = (bitmap & (bitmap - 1)) != 0;
  if (persist) {
    return faults + (several ? ". Their causes are" : ". Its cause is") +
           " still present: deal with " + (several ? "them" : "it") + ", then clear again";
  }
  return "faulted: " + faults + (several ? ". Clear the faults" : ". Clear the fault") +
         " (palpa clear; ClearFault in the library) once the cause is gone, then send again";
}

Outcome Device::StreamRefused(Status s, uint32_t detail, const char* what,
                              std::vector<std::string> notes) {
  Outcome o{s, std::string(what) + ": " + pp::StatusName(s), std::move(notes)};
  if (s == Status::kFaulted && detail != 0) {
    o.faults = detail;
    o.message = std::string(what) + ": " + FaultText(detail, false);
  } else if (s == Status::kNoSession && !link_->session_end().empty()) {
    o.message += " (" + link_->session_end() + ")";
  }
  return o;
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
    return Outcome{Status::kNotFound, FingerName(finger) + " does not exist", {}};
  if (modes_[finger] == mode) return {};
  const Outcome o = FromCommand(link_->Command(pp::SetFingerMode{finger, mode}), "set finger mode");
  if (o.ok()) modes_[finger] = mode;
  return o;
}

Outcome Device::Set(const std::vector<FingerRequest>& requests, bool wait,
                    std::vector<Applied>* applied) {
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
                     FingerName(r.finger) + " does not exist (this board has fingers " +
                         std::to_string(options_.number_from) + " to " +
                         std::to_string(b.finger_count - 1 + options_.number_from) + ")",
                     {}};
    }
    // Raw pressures do not go through the curves; everything else does.
    if (options_.invalid_calibration_is_error && r.request.kind != TargetKind::kPressureKpa &&
        !calibration_problems_[r.finger].empty()) {
      return Outcome{
          Status::kBadValue,
          FingerName(r.finger) + ": " + calibration_problems_[r.finger] + " (nothing was sent)",
          {}};
    }
    mapped.push_back(MapRequest(b.fingers[r.finger], options_.levels, curves_[r.finger], r.request,
                                options_.range_policy));
    if (mapped.back().status != Status::kOk) {
      return Outcome{mapped.back().status, FingerName(r.finger) + ": " + mapped.back().error, {}};
    }
  }
  for (size_t i = 0; i < requests.size(); ++i) {
    const FingerRequest& r = requests[i];
    const Mapped& m = mapped[i];
    std::string map = m.note;
    while (!map.empty() && (map.back() == ' ' || map.back() == ';')) map.pop_back();
    out.notes.push_back(FingerName(r.finger) + ": " + map);
    if (applied != nullptr) {
      const pp::FingerSummary& f = b.fingers[r.finger];
      applied->push_back(Applied{r.finger, r.request, m.raw, m.target / 1000.0,
                                 OutputUnitName(f.kind), m.from_table, m.table_kpa, f.line_a,
                                 f.line_b, m.line_a_pa, m.line_b_pa, map});
    }
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
  uint32_t detail = 0;
  if (targets.entry_count > 0) {
    const uint32_t g = link_->StreamTargets(targets);
    const Status s = wait ? link_->WaitTargetsApplied(g, timeout, &detail) : Status::kOk;
    if (s != Status::kOk)
      return StreamRefused(s, detail, "the board did not apply the targets", out.notes);
  }
  if (lines.entry_count > 0) {
    const uint32_t g = link_->StreamSetpoints(lines);
    const Status s = wait ? link_->WaitSetpointsApplied(g, timeout, &detail) : Status::kOk;
    if (s != Status::kOk)
      return StreamRefused(s, detail, "the board did not apply the setpoints", out.notes);
  }
  return out;
}

Outcome Device::SetLines(const std::vector<std::pair<uint8_t, double>>& kpa, bool wait) {
  const pp::HelloReply b = link_->board();
  pp::SetLineSetpoints lines{};
  for (const auto& [line, value] : kpa) {
    if (line >= b.line_count)
      return Outcome{Status::kNotFound, LineName(line) + " does not exist", {}};
    const double pa = value * 1000;
    if (!std::isfinite(value)) {
      char text[96];
      std::snprintf(text, sizeof(text), "%s: %g kPa is not a finite number", LineName(line).c_str(),
                    value);
      return Outcome{Status::kOutOfRange, text, {}};
    }
    if (pa < b.lines[line].limit_min_pa || pa > b.lines[line].limit_max_pa) {
      char text[160];
      std::snprintf(text, sizeof(text), "%s: %g kPa is outside its limits %g … %g kPa",
                    LineName(line).c_str(), value, b.lines[line].limit_min_pa / 1000.0,
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
  uint32_t detail = 0;
  const Status s = wait ? link_->WaitSetpointsApplied(g, options_.link.command_timeout_ms, &detail)
                        : Status::kOk;
  if (s != Status::kOk)
    return StreamRefused(s, detail, "the board did not apply the setpoints", {});
  return {};
}

Outcome Device::EStop() {
  const Status s = link_->EStop();
  return s == Status::kOk ? Outcome{} : Outcome{s, "the board did not acknowledge the EStop", {}};
}

Outcome Device::ClearFault(uint32_t mask) {
  // The board keeps its outputs safe after clearing until new setpoints arrive.
  const CommandResult r = link_->Command(pp::ClearFault{mask});
  Outcome o = FromCommand(r, "clear fault");
  if (r.status == Status::kConditionPersists && r.detail != 0) {  // detail: the faults that stay
    o.faults = r.detail;
    o.message = "clear fault: condition_persists: " + FaultText(r.detail, true);
  }
  return o;
}

Result<pp::Diagnostics> Device::Diagnostics() {
  const CommandResult r = link_->Command(pp::GetDiagnostics{});
  pp::Diagnostics d{};
  if (r.status == Status::kOk && r.Reply(d)) return d;
  return {r.status == Status::kOk ? Status::kBadValue : r.status,
          std::string("diagnostics: ") + pp::StatusName(r.status) + " " + r.message};
}

Result<pp::LoopStats> Device::LoopStats() {
  const CommandResult r = link_->Command(pp::GetLoopStats{});
  pp::LoopStats s{};
  if (r.status == Status::kOk && r.Reply(s)) return s;
  return {r.status == Status::kOk ? Status::kBadValue : r.status,
          std::string("loop statistics: ") + pp::StatusName(r.status) + " " + r.message};
}

}  // namespace palpa::host
