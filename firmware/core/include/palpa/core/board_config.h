// The board's whole configuration, held as the protocol's own Configure* records, with
// validation, the staged-blob encoding used for uploads and flash, and its CRC.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "palpa/protocol/messages_config.h"
#include "palpa/protocol/status.h"

namespace palpa::core {

using protocol::Status;

struct BoardConfig {
  protocol::ConfigureBoard board{};
  uint8_t line_count = 0;
  std::array<protocol::ConfigureLine, protocol::kMaxLines> lines{};
  uint8_t finger_count = 0;
  std::array<protocol::ConfigureFinger, protocol::kMaxFingers> fingers{};
};

/// What a validation found wrong: the section, its index and a short reason for people.
struct ConfigError {
  protocol::ConfigSection section = protocol::ConfigSection::kBoard;
  uint8_t index = 0;
  const char* reason = "";
  /// Nack detail: section << 8 | index.
  uint32_t detail() const { return static_cast<uint32_t>(section) << 8 | index; }
};

/// A board's own check of a line (BoardIo::line_check): why its hardware refuses the line, or
/// nullptr.
using LineCheck = const char* (*)(const protocol::ConfigureLine& line);

/// Checks everything a single record cannot: hard ceilings, limits against each other, monotone
/// curves, gains within the pressure loop's stable region, line ownership by fingers.
Status ValidateLine(const protocol::ConfigureLine& line, ConfigError* error);
Status ValidateFinger(const protocol::ConfigureFinger& finger, const BoardConfig& config,
                      ConfigError* error);
Status ValidateConfig(const BoardConfig& config, ConfigError* error);

/// Largest blob the board stores (flash) and accepts (staged upload: protocol::kMaxStagedBytes).
inline constexpr size_t kMaxConfigBlob = 8192;

/// Writes config as records [u16 body length][u8 type][body]: board, lines, fingers.
/// Returns the blob size, or kOverflow.
protocol::Result<size_t> EncodeConfigBlob(const BoardConfig& config, uint8_t* out, size_t capacity);

/// Applies the records of a blob onto `config` (records not present keep their values).
/// Each record is decoded with the codec's range checks; *error names the record.
Status ApplyConfigBlob(const uint8_t* blob, size_t size, BoardConfig& config, ConfigError* error);

/// CRC-32 of the canonical blob of config (reported in ConfigReport, stored in flash).
uint32_t ConfigCrc(const BoardConfig& config);

/// Index of the finger using `line`, or protocol::kNoLine.
uint8_t FingerOfLine(const BoardConfig& config, uint8_t line);

}  // namespace palpa::core
