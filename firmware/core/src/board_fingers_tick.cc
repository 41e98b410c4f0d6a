// The tick's finger stage over the board's fingers (at -O2, with the finger step inlined).
#include "finger_step.h"
#include "palpa/core/internal/board_fingers.h"

namespace palpa::core {

void BoardFingers::Step(const FingerTick& tick, const LineObservation* seen,
                        const LineState* lines) {
  const FingerParams* p = params_.data();
  const FingerParams* const end = p + count_;
  FingerState* s = state_.data();
  for (; p != end; ++p, ++s) {
    if (s->mode != protocol::FingerMode::kTarget) continue;  // raw: the host drives the lines
    const LineReading& reading = seen[p->driven_line].reading;
    StepFingerInline(*p, *s, reading.valid ? reading.pa : lines[p->driven_line].reference_pa, tick);
  }
}

}  // namespace palpa::core
