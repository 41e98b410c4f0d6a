// Where things live in a board's flash (DESIGN §9): the bootloader, two direct-XIP image slots,
// two alternating boot-state sectors and the configuration copies. Offsets from flash start.
#pragma once

#include <cstdint>

namespace palpa::core {

struct FlashLayout {
  uint32_t sector_size = 0;
  uint32_t bootloader_size = 0;      ///< at 0; write-protected on hardware
  uint32_t slot_offset[2] = {0, 0};  ///< each image linked to run from its own slot
  uint32_t slot_size = 0;
  uint32_t state_offset[2] = {0, 0};  ///< one sector each, used alternately
  uint32_t config_offset = 0;         ///< two sectors: ConfigStore's copies
  uint32_t total = 0;
  uint32_t xip_base = 0;  ///< where flash appears in the address map (an image's load address)
};

/// The layout of the simulated board and the MPS2 image (8 KiB sectors, 512 KiB of flash):
/// bootloader 32 KiB, slots of 192 KiB (an image is ≤ 64 KiB today: room to grow), state and
/// configuration two sectors each.
inline constexpr FlashLayout kDefaultLayout{8 * 1024,                  // sector
                                            32 * 1024,                 // bootloader
                                            {32 * 1024, 224 * 1024},   // slots
                                            192 * 1024,                // slot size
                                            {416 * 1024, 424 * 1024},  // boot state
                                            432 * 1024,  // configuration (two sectors)
                                            512 * 1024,
                                            0};

}  // namespace palpa::core
