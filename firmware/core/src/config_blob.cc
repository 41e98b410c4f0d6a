// The configuration as a blob of Configure* records: staged uploads and flash use the same bytes.
#include "palpa/core/board_config.h"
#include "palpa/protocol/codec.h"
#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

using protocol::ConfigSection;

template <class M>
bool AppendRecord(const M& message, uint8_t* out, size_t capacity, size_t& size) {
  if (capacity - size < 3) return false;
  const auto body = protocol::EncodeBody(message, out + size + 3, capacity - size - 3);
  if (!body.ok()) return false;
  out[size] = static_cast<uint8_t>(body.value);
  out[size + 1] = static_cast<uint8_t>(body.value >> 8);
  out[size + 2] = static_cast<uint8_t>(message.kInfo.type);
  size += 3 + body.value;
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
  size_t at = 0;
  uint8_t record = 0;
  while (at < size) {
    if (size - at < 3)
      return RecordError(error, ConfigSection::kBoard, record, "truncated record header",
                         Status::kBadLength);
    const size_t length = static_cast<size_t>(blob[at]) | static_cast<size_t>(blob[at + 1]) << 8;
    const uint8_t type = blob[at + 2];
    const uint8_t* body = blob + at + 3;
    if (size - at - 3 < length)
      return RecordError(error, ConfigSection::kBoard, record, "record longer than the blob",
                         Status::kBadLength);
    Status status = Status::kOk;
    if (type == static_cast<uint8_t>(protocol::MessageType::kConfigureBoard)) {
      status = protocol::DecodeBody(body, length, config.board);
      if (status != Status::kOk)
        return RecordError(error, ConfigSection::kBoard, 0, "board record", status);
    } else if (type == static_cast<uint8_t>(protocol::MessageType::kConfigureLine)) {
      protocol::ConfigureLine line{};
      status = protocol::DecodeBody(body, length, line);
      if (status != Status::kOk)
        return RecordError(error, ConfigSection::kLine, record, "line record", status);
      if (line.line > config.line_count)
        return RecordError(error, ConfigSection::kLine, line.line, "lines must be added in order",
                           Status::kOutOfRange);
      config.lines[line.line] = line;
      if (line.line == config.line_count) ++config.line_count;
    } else if (type == static_cast<uint8_t>(protocol::MessageType::kConfigureFinger)) {
      protocol::ConfigureFinger finger{};
      status = protocol::DecodeBody(body, length, finger);
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
    at += 3 + length;
    ++record;
  }
  return Status::kOk;
}

uint32_t ConfigCrc(const BoardConfig& config) {
  // Record by record through a small buffer: the CRC of the blob without holding the blob.
  uint8_t record[3 + 480];
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
