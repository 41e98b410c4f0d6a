// A board configuration as JSON: what `palpa config show` prints and `config load|set` read.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "palpa/core/board_config.h"
#include "palpa/host/file_read.h"

namespace palpa::host {

/// `palpa config show` of the largest board (eight lines, eight fingers with 80-parameter
/// compensators) prints about 30 KiB.
inline constexpr FileLimits kConfigFileLimits{"configuration file", 256 * 1024};

/// Configuration files number lines and fingers from 0, as the wire does (the command line and
/// palpa's messages number them from 1); every file says so in this key, and a file that gives
/// another numbering is refused.
inline constexpr const char* kConfigNumberingKey = "numbering";
inline constexpr const char* kConfigNumbering = "from 0, as on the wire";

/// Every configured section as its Configure* message's fields: {numbering, board, lines[],
/// fingers[]}; a finger without a second line has "line_b": null.
nlohmann::json ConfigToJson(const core::BoardConfig& config);

/// Applies a (partial) configuration onto `config`: sections and fields present replace those of
/// `config`, a line or finger one past the last adds it. Throws std::runtime_error naming the
/// field's path ("lines[2]: field 'trim_kp': expected a number") and then leaves `config` as it
/// was. Each field is held to its wire range; cross checks are ValidateConfig's.
void ApplyConfigJson(const nlohmann::json& patch, core::BoardConfig& config);

/// Sets one field of the board, of line `index` or of finger `index` (from 0); throws naming the
/// field ("unknown field 'slew' (the fields: kind, ...)") and then leaves `config` as it was.
void SetConfigField(protocol::ConfigSection section, uint8_t index, const std::string& field,
                    const nlohmann::json& value, core::BoardConfig& config);

}  // namespace palpa::host
