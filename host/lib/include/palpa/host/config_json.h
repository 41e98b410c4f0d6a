// A board configuration as JSON: what `palpa config show` prints and `config load|set` read.
#pragma once

#include <nlohmann/json.hpp>

#include "palpa/core/board_config.h"
#include "palpa/host/file_read.h"

namespace palpa::host {

/// `palpa config show` of the largest board (eight lines, eight fingers with 80-parameter
/// compensators) prints about 30 KiB.
inline constexpr FileLimits kConfigFileLimits{"configuration file", 256 * 1024};

/// Every configured section as its Configure* message's fields: {board, lines[], fingers[]}.
nlohmann::json ConfigToJson(const core::BoardConfig& config);

/// Applies a (partial) configuration onto `config`: sections and fields present replace those of
/// `config`, a line or finger one past the last adds it. Throws std::runtime_error naming the
/// field's path ("lines[2]: field 'trim_kp': expected a number") and then leaves `config` as it
/// was. Each field is held to its wire range; cross checks are ValidateConfig's.
void ApplyConfigJson(const nlohmann::json& patch, core::BoardConfig& config);

}  // namespace palpa::host
