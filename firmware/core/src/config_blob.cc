// The configuration as a blob of Configure* records: staged uploads and flash use the same bytes.
#include "palpa/core/board_config.h"
#include "palpa/protocol/config_records.h"
#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

using protocol::ConfigSection;

template <class M>
bool AppendRecord(const M& message, uint8_t* out, size_t capacity, size_t& size) {
  const auto record = protocol::EncodeRecord(message, out + size, capacity - size);
  if (!record.ok()) return false;
  size += record.value;
  return true;
}

Status RecordError(ConfigError* error, ConfigSection section, uint8_t index, const char* reason,
                   Status status) {
  if (error != nullptr) *error = ConfigError{section, index, reason};
  return status;
}

}  // namespace

protocol::Result<size_t> EncodeConfigBlob(const BoardConfig& config, uint8_t* out,
                                          size_t capacity) {
  size_t size = 0;
  if (!AppendRecord(config.board, out, capacity, size)) return Status::kOverflow;
  for (uint8_t i = 0; i < config.line_count; ++i) {
    if (!AppendRecord(config.lines[i], out, capacity, size)) return Status::kOverflow;
  }
  for (uint8_t i = 0; i < config.finger_count; ++i) {
    if (!AppendRecord(config.fingers[i], out, capacity, size)) return Status::kOverflow;
  }
  return size;
}

Status ApplyConfigBlob(const uint8_t* blob, size_t size, BoardConfig& config, ConfigError* error) {
  protocol::RecordReader reader(blob, size);
  while (!reader.done()) {
    const uint8_t record = reader.index();
    protocol::Record r;
    const char* reason = "";
    if (reader.Next(r, &reason) != Status::kOk)
      return RecordError(error, ConfigSection::kBoard, record, reason, Status::kBadLength);
    Status status = Status::kOk;
    if (r.type == static_cast<uint8_t>(protocol::MessageType::kConfigureBoard)) {
      status = protocol::DecodeBody(r.body, r.size, config.board);
      if (status != Status::kOk)
        return RecordError(error, ConfigSection::kBoard, 0, "board record", status);
    } else if (r.type == static_cast<uint8_t>(protocol::MessageType::kConfigureLine)) {
      protocol::ConfigureLine line{};
      status = protocol::DecodeBody(r.body, r.size, line);
      if (status != Status::kOk)
        return RecordError(error, ConfigSection::kLine, record, "line record", status);
      if (line.line > config.line_count)
        return RecordError(error, ConfigSection::kLine, line.line, "lines must be added in order",
                           Status::kOutOfRange);
      config.lines[line.line] = line;
      if (line.line == config.line_count) ++config.line_count;
    } else if (r.type == static_cast<uint8_t>(protocol::MessageType::kConfigureFinger)) {
      protocol::ConfigureFinger finger{};
      status = protocol::DecodeBody(r.body, r.size, finger);
      if (status != Status::kOk)
        return RecordError(error, ConfigSection::kFinger, record, "finger record", status);
      if (finger.finger > config.finger_count)
        return RecordError(error, ConfigSection::kFinger, finger.finger,
                           "fingers must be added in order", Status::kOutOfRange);
      config.fingers[finger.finger] = finger;
      if (finger.finger == config.finger_count) ++config.finger_count;
    } else {
      return RecordError(error, ConfigSection::kBoard, record, "not a configuration record",
                         Status::kUnsupported);
    }
  }
  return Status::kOk;
}

uint32_t ConfigCrc(const BoardConfig& config) {
  // Record by record through a small buffer: the CRC of the blob without holding the blob.
  uint8_t record[protocol::kRecordHeaderSize + 480];
  uint32_t crc = 0;
  auto add = [&](const auto& message) {
    size_t size = 0;
    if (AppendRecord(message, record, sizeof(record), size))
      crc = protocol::Crc32Update(crc, record, size);
  };
  add(config.board);
  for (uint8_t i = 0; i < config.line_count; ++i) add(config.lines[i]);
  for (uint8_t i = 0; i < config.finger_count; ++i) add(config.fingers[i]);
  return crc;
}

}  // namespace palpa::core
