// Configuration persisted in flash: two copies, each [header | blob], the newest valid one wins.
#pragma once

#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/hal/flash.h"

namespace palpa::core {

/// Two sectors at `base` and `base + sector_size` hold one copy each. A save writes the older
/// copy: erase, program the blob, then the header last, so a torn save leaves that copy invalid
/// and the other one intact.
class ConfigStore {
 public:
  /// flash may be nullptr (a board without storage): Load gives the factory defaults and Save
  /// and Erase answer kUnavailable.
  ConfigStore(hal::Flash* flash, uint32_t base) : flash_(flash), base_(base) {}

  enum class Source : uint8_t { kFactory, kFlash };

  /// Sets `config` to the newest valid copy, or to `factory` when no copy is valid.
  Source Load(const BoardConfig& factory, BoardConfig& config);

  /// Writes `config` as the next copy. kIoError on a flash failure, kOverflow when the blob does
  /// not fit a sector.
  Status Save(const BoardConfig& config);

  /// Erases both copies: the next boot uses the factory defaults.
  Status Erase();

  uint32_t sequence() const { return sequence_; }

 private:
  struct Header {
    uint32_t magic;
    uint32_t sequence;
    uint32_t length;
    uint32_t crc;  ///< CRC-32 of the blob
    uint32_t header_crc;
  };
  bool ReadHeader(uint8_t copy, Header& header);
  bool ReadCopy(uint8_t copy, const Header& header, const BoardConfig& factory,
                BoardConfig& config);

  hal::Flash* flash_;
  uint32_t base_;
  uint32_t sequence_ = 0;
  uint8_t newest_ = 1;  ///< the copy written last (the next save goes to the other)
};

}  // namespace palpa::core
