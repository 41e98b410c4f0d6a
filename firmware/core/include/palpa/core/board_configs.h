// The board configurations compiled into every image (from firmware/core/configs/*.json).
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"

namespace palpa::core {

struct NamedBoardConfig {
  const char* name;
  const BoardConfig* config;
};

extern const NamedBoardConfig kBoardConfigs[];
extern const uint8_t kBoardConfigCount;

/// The configuration called `name`, or nullptr.
const BoardConfig* FindBoardConfig(const char* name);

}  // namespace palpa::core
