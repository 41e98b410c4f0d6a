// The reset cause a board shell's fault handlers leave for the next boot, in RAM startup does
// not touch (.noinit). Shared by every board shell.
#pragma once

#include <cstdint>

#include "palpa/protocol/enums.h"

namespace palpa::boards {

/// A reset cause kept across a reset in .noinit RAM, valid only with its check word.
struct ResetRecord {
  uint32_t magic;
  uint32_t cause;
  uint32_t check;
  uint32_t boot_count;
  static constexpr uint32_t kMagic = 0x52535443u;
  void Set(protocol::ResetCause c) {
    magic = kMagic;
    cause = static_cast<uint32_t>(c);
    check = ~cause;
  }
  /// The cause recorded before this reset (power-on when nothing valid was recorded), cleared.
  protocol::ResetCause Take() {
    const bool valid = magic == kMagic && check == ~cause &&
                       cause < static_cast<uint32_t>(protocol::ResetCause::kCount);
    const auto c =
        valid ? static_cast<protocol::ResetCause>(cause) : protocol::ResetCause::kPowerOn;
    boot_count = valid ? boot_count + 1 : 1;
    magic = 0;
    return c;
  }
};

}  // namespace palpa::boards
