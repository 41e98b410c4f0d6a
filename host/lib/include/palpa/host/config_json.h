// A board configuration as JSON: what `palpa config show` prints and `config load|set` read.
#pragma once

#include <nlohmann/json.hpp>

#include "palpa/core/board_config.h"

namespace palpa::host {

/// Every configured section as its Configure* message's fields: {board, lines[], fingers[]}.
nlohmann::json ConfigToJson(const core::BoardConfig& config);

/// Applies a (partial) configuration onto `config`: sections and fields present replace those of
/// `config`, a line or finger one past the last adds it. Throws std::runtime_error naming the
/// field's path ("lines[2]: field 'trim_kp': expected a number") and then leaves `config` as it
/// was. Each field is held to its wire range; cross checks are ValidateConfig's.
void ApplyConfigJson(const nlohmann::json& patch, core::BoardConfig& config);

}  // namespace palpa::host
