// Internal to firmware/core: a staged configuration upload — the parts received so far, in
// order, with their CRC, until a commit applies them onto a candidate configuration.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/protocol/messages_admin.h"

namespace palpa::core {

class StagedConfig {
 public:
  /// A new upload of `total_bytes` (what was staged before is dropped).
  void Begin(const protocol::StagedBegin& m) {
    expected_ = m.total_bytes;
    received_ = 0;
    crc_ = 0;
  }
  /// The next part: kUnavailable without a Begin, kOutOfRange (with what was received in
  /// `detail`) for a part out of order or beyond the announced size.
  Status Part(const protocol::StagedPart& m, uint32_t& detail);
  /// Ends the upload (one commit per begin, whatever happens): kStagedIncomplete (received bytes
  /// in `detail`) or kCrcError, or kOk when every byte arrived as sent.
  Status Commit(const protocol::StagedCommit& m, uint32_t& detail);
  /// Applies the committed upload's records onto `candidate`: the first bad record's status with
  /// its section and index in `detail`.
  Status ApplyTo(BoardConfig& candidate, uint32_t& detail) const;

 private:
  std::array<uint8_t, protocol::kMaxStagedBytes> bytes_{};
  uint16_t expected_ = 0;
  uint16_t received_ = 0;
  uint16_t committed_ = 0;  ///< size of the last upload committed whole
  uint32_t crc_ = 0;        ///< of the bytes received, part by part: the commit only compares
};

}  // namespace palpa::core
