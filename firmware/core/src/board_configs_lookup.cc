// Lookup of the compiled-in board configurations by name.
#include "palpa/core/board_configs.h"
#include "palpa/core/config_literals.h"

namespace palpa::core {

const BoardConfig* FindBoardConfig(const char* name) {
  for (uint8_t i = 0; i < kBoardConfigCount; ++i) {
    if (SameText(kBoardConfigs[i].name, name)) return kBoardConfigs[i].config;
  }
  return nullptr;
}

}  // namespace palpa::core
