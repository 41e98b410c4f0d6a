// Device: configuring the board — lines, board, fingers (staged when large), saving, factory
// reset — and reading its configuration back, section by section.
#include "palpa/host/device.h"

#include <string>
#include <vector>

#include "palpa/protocol/config_records.h"
#include "palpa/protocol/crc32.h"

namespace palpa::host {

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
  const auto board = ReadBoard();
  if (board.ok()) {
    link_->SetHostTimeout(board.value.host_timeout_us);
  } else {
    o.notes.push_back("could not read back the host-silence timeout (" + board.message +
                      "): heartbeats keep their period until the next session");
  }
  return o;
}

Outcome Device::ConfigureFinger(const pp::ConfigureFinger& finger) {
  uint8_t record[pp::kRecordHeaderSize + 512];
  const auto size = pp::EncodeRecord(finger, record, sizeof(record));
  if (!size.ok()) return Outcome{size.status, "configure finger: cannot encode", {}};
  if (size.value - pp::kRecordHeaderSize <= pp::kMaxBodySize)
    return FromCommand(link_->Command(finger), "configure finger");
  return ConfigureStaged(record, size.value);
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
                 std::to_string((r.detail & 0xFFu) + options_.number_from) + ")";
  }
  return o;
}

template <class M>
Result<M> Device::ReadSection(pp::ConfigSection section, uint8_t index) {
  std::vector<uint8_t> body;
  for (uint16_t offset = 0;;) {
    const CommandResult r = link_->Command(pp::GetConfig{section, index, offset});
    pp::ConfigReport report{};
    if (r.status != Status::kOk || !r.Reply(report)) {
      return {r.status == Status::kOk ? Status::kBadValue : r.status,
              std::string("read configuration: ") + pp::StatusName(r.status) + " " + r.message};
    }
    body.insert(body.end(), report.data.begin(), report.data.begin() + report.data_size);
    offset = static_cast<uint16_t>(offset + report.data_size);
    if (offset >= report.total_bytes || report.data_size == 0) break;
  }
  M m{};
  pp::FieldError field;
  const Status s = pp::DecodeBody(body.data(), body.size(), m, &field);
  if (s != Status::kOk) {
    return {s, std::string("the board's configuration does not decode at ") +
                   (field.field ? field.field : "?")};
  }
  return m;
}

Result<pp::ConfigureLine> Device::ReadLine(uint8_t line) {
  return ReadSection<pp::ConfigureLine>(pp::ConfigSection::kLine, line);
}
Result<pp::ConfigureFinger> Device::ReadFinger(uint8_t finger) {
  return ReadSection<pp::ConfigureFinger>(pp::ConfigSection::kFinger, finger);
}
Result<pp::ConfigureBoard> Device::ReadBoard() {
  return ReadSection<pp::ConfigureBoard>(pp::ConfigSection::kBoard, 0);
}

}  // namespace palpa::host
