// The board's fingers: a configuration applied, targets and modes from the host (the tick's finger
// stage is in board_fingers_tick.cc).
#include "palpa/core/internal/board_fingers.h"
#include "palpa/core/internal/board_lines.h"

namespace palpa::core {

void BoardFingers::Apply(const BoardConfig& live) {
  count_ = live.finger_count;
  home_dwell_us_ = static_cast<uint32_t>(live.board.home_dwell_ms) * 1000;
  for (uint8_t i = 0; i < protocol::kMaxLines; ++i) line_owner_[i] = FingerOfLine(live, i);
  for (uint8_t f = 0; f < live.finger_count; ++f) {
    const protocol::ConfigureFinger& finger = live.fingers[f];
    const bool jamming = finger.kind == protocol::FingerKind::kJamming;
    const protocol::ConfigureLine& driven = live.lines[jamming ? finger.line_b : finger.line_a];
    const float drive_limit =
        static_cast<float>(jamming ? -driven.limit_min_pa : driven.limit_max_pa);
    params_[f] = MakeFingerParams(finger, drive_limit);
    state_[f].target = 0;
  }
}

Status BoardFingers::Accept(const protocol::SetFingerTargets& m, uint32_t& detail) {
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    const protocol::FingerTarget& e = m.entries[i];
    detail = i;
    if (e.finger >= count_) return Status::kNotFound;
    const FingerParams& p = params_[e.finger];
    if (state_[e.finger].mode != protocol::FingerMode::kTarget) return Status::kWrongMode;
    if (e.unit != UnitOf(p.kind)) return Status::kBadValue;
    if (e.target > p.max_target) return Status::kOutOfRange;
  }
  detail = 0;
  for (uint8_t i = 0; i < m.entry_count; ++i) {
    state_[m.entries[i].finger].target = static_cast<float>(m.entries[i].target);
  }
  return Status::kOk;
}

Status BoardFingers::SetMode(const protocol::SetFingerMode& m, BoardLines& lines,
                             uint32_t& detail) {
  detail = m.finger;
  if (m.finger >= count_) return Status::kNotFound;
  detail = 0;
  FingerState& s = state_[m.finger];
  if (s.mode == m.mode) return Status::kOk;
  s.mode = m.mode;
  const FingerParams& p = params_[m.finger];
  if (m.mode == protocol::FingerMode::kRaw) {
    // Raw setpoints start where the finger's lines are now, until the host sends its own.
    lines.HoldWhereItIs(p.line_a);
    if (p.line_b != protocol::kNoLine) lines.HoldWhereItIs(p.line_b);
  } else {
    RequireHoming(s);  // back to target mode: the compensator's memory is stale
  }
  MarkRawLines(lines.flags());
  return Status::kOk;
}

void BoardFingers::MarkRawLines(uint8_t* line_flags) const {
  for (uint8_t i = 0; i < protocol::kMaxLines; ++i) line_flags[i] = 0;
  for (uint8_t f = 0; f < count_; ++f) {
    if (state_[f].mode != protocol::FingerMode::kRaw) continue;
    const FingerParams& p = params_[f];
    line_flags[p.line_a] = protocol::line_status::kRaw;
    if (p.line_b != protocol::kNoLine) line_flags[p.line_b] = protocol::line_status::kRaw;
  }
}

}  // namespace palpa::core
