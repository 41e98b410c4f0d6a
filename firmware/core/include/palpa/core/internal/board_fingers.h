// Internal to firmware/core: the board's fingers — what each is configured as (with its
// compensator's tables), its mode, target, homing and compensator memory. The finger stage of
// the tick, targets and modes from the host go through here.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/board_config.h"
#include "palpa/core/finger.h"
#include "palpa/core/line_pipeline.h"
#include "palpa/core/supervisor.h"
#include "palpa/protocol/messages_stream.h"

namespace palpa::core {

class BoardLines;

class BoardFingers {
 public:
  /// A new live configuration: parameters and tables built, targets 0 (the board holds, so every
  /// finger re-homes).
  void Apply(const BoardConfig& live);
  /// Every finger re-homes before following targets again (outputs were or go safe).
  void Hold() {
    for (FingerState& f : state_) RequireHoming(f);
  }

  /// The finger stage: fingers in target mode write their lines' setpoints and status bits.
  /// The compensator's memory follows what each driven line applied: its reading in `seen`, or
  /// where the regulator model in `lines` has the pressure when there is none. Out of line, so
  /// instruction counts can bracket the finger stage (its steps are inlined).
  [[gnu::noinline]] void Step(const FingerTick& tick, const LineObservation* seen,
                              const LineState* lines);

  /// Targets from the host: each entry names a configured finger in target mode, in its unit,
  /// within what its inverse covers. kNotFound / kWrongMode / kBadValue / kOutOfRange with the
  /// entry's index in `detail`; nothing is applied unless every entry passes.
  Status Accept(const protocol::SetFingerTargets& m, uint32_t& detail);
  /// Target or raw mode. A finger going raw leaves its lines stepping towards where they are; one
  /// going back to target mode re-homes (its compensator's memory is stale).
  Status SetMode(const protocol::SetFingerMode& m, BoardLines& lines, uint32_t& detail);

  /// The host may set `line` directly: no finger drives it, or its finger is in raw mode.
  bool TakesRawSetpoints(uint8_t line) const {
    const uint8_t owner = line_owner_[line];
    return owner == protocol::kNoLine || state_[owner].mode == protocol::FingerMode::kRaw;
  }
  /// The lines' finger status bits from the modes: kRaw on a raw finger's lines, nothing else.
  void MarkRawLines(uint8_t* line_flags) const;

  protocol::FingerMode mode(uint8_t finger) const { return state_[finger].mode; }
  uint32_t home_dwell_us() const { return home_dwell_us_; }

 private:
  uint8_t count_ = 0;
  uint32_t home_dwell_us_ = 0;
  std::array<FingerParams, protocol::kMaxFingers> params_{};
  std::array<FingerState, protocol::kMaxFingers> state_{};
  std::array<uint8_t, protocol::kMaxLines> line_owner_{};  ///< the finger driving each line
};

}  // namespace palpa::core
