// Fault conditions: host silence, over-limit, implausible or stuck sensor, configuration CRC,
// leak, E-stop pin, pump run time, output write. Every one latches into the same bitmap.
#include "palpa/core/supervisor.h"

#include "palpa/core/internal/float_ops.h"

namespace palpa::core {
namespace {

using protocol::Fault;
using protocol::FaultBit;

/// True once `condition` has held continuously for longer than `window`.
bool HeldFor(bool condition, bool& timing, uint64_t& since, uint64_t now, uint64_t window) {
  if (!condition) {
    timing = false;
    return false;
  }
  if (!timing) {
    timing = true;
    since = now;
  }
  return now - since > window;
}

}  // namespace

SupervisorSettings MakeSupervisorSettings(const protocol::ConfigureBoard& board) {
  SupervisorSettings s;
  s.host_timeout_us = board.host_timeout_us;
  s.leak_timeout_us = static_cast<uint64_t>(board.leak_timeout_ms) * 1000;
  s.pump_max_run_us = static_cast<uint64_t>(board.pump_max_run_ms) * 1000;
  s.sensor_window_us = static_cast<uint64_t>(board.sensor_window_ms) * 1000;
  s.tolerance_pa = static_cast<float>(board.sensor_tolerance_pa);
  return s;
}

void LatchFault(SupervisorState& s, Fault fault, uint64_t now_us, int32_t detail) {
  const uint32_t bit = FaultBit(fault);
  if ((s.latched & bit) != 0) return;
  s.latched |= bit;
  s.history[s.history_next] = protocol::FaultRecord{now_us, static_cast<uint8_t>(fault), detail};
  s.history_next = static_cast<uint8_t>((s.history_next + 1) % protocol::kMaxFaultRecords);
  if (s.history_count < protocol::kMaxFaultRecords) ++s.history_count;
}

uint32_t Supervise(const SupervisorSettings& settings, SupervisorState& s,
                   const SupervisorInput& in) {
  const uint32_t before = s.latched;
  uint32_t active = 0;
  // Written by the first raise of a fault and read only for raised faults: no per-tick zeroing
  // (the C library's memset is a byte loop).
  int32_t detail[static_cast<int>(Fault::kCount)];
  auto raise = [&](Fault f, int32_t d) {
    if ((active & FaultBit(f)) == 0) detail[static_cast<int>(f)] = d;
    active |= FaultBit(f);
  };

  // A host that vanished from a board it left safe is no fault: the session just ends.
  s.host_silent = HostSilent(settings, in);
  if (s.host_silent && in.actuating) {
    raise(Fault::kHostSilence, static_cast<int32_t>((in.now_us - in.last_host_frame_us) / 1000));
  }
  if (in.estop_pin) raise(Fault::kEStopPin, 0);
  if (!in.config_intact) raise(Fault::kConfigCrc, 0);
  // A regulator keeps its last code, a valve or enable its last level: the outputs that still
  // answer (the valves fall back as their enables stop toggling) take the pressure away.
  if (in.failed_output != kNoFailedOutput) raise(Fault::kOutputWrite, in.failed_output);

  // Every tick, every line: a reading that is no pressure, or one beyond the limits.
  if (in.readings.first_invalid != protocol::kNoLine)
    raise(Fault::kImplausibleSensor, in.readings.first_invalid);
  if (in.readings.first_beyond != protocol::kNoLine)
    raise(Fault::kOverLimit, static_cast<int32_t>(in.readings.beyond_pa));
  const float tol = settings.tolerance_pa;
  const bool pump_wanted = in.vacuum_demand && !in.safe;

  // The slow monitors judge conditions held for seconds: one line slot a tick, so each line
  // every kMaxLines ticks (8 ms). A condition is then seen as held when it holds at each visit.
  const uint8_t slot = s.slow_slot;
  s.slow_slot = static_cast<uint8_t>((slot + 1) % protocol::kMaxLines);
  const LineObservation& o = in.lines[slot];
  if (o.configured && o.has_sensor && o.reading.valid) {
    LineMonitor& m = s.lines[slot];
    // More pressure than the regulator was told to make, for longer than the chamber settles.
    const bool beyond_model = Abs(o.reading.pa) > Abs(o.reference_pa) + tol;
    if (HeldFor(beyond_model, m.implausible_timing, m.implausible_since, in.now_us,
                settings.sensor_window_us)) {
      raise(Fault::kImplausibleSensor, slot);
    }
    // Stuck: the very same counts while the command moved by more than the tolerance.
    if (o.raw_counts != m.stuck_counts) {
      m.stuck_counts = o.raw_counts;
      m.stuck_since = in.now_us;
      m.stuck_reference = o.reference_pa;
    } else if (Abs(o.reference_pa - m.stuck_reference) > tol &&
               in.now_us - m.stuck_since > settings.sensor_window_us) {
      raise(Fault::kImplausibleSensor, slot);
    }
    // Leak: the model has settled on the setpoint but the chamber stays short of it.
    const bool short_of_setpoint = o.closed_loop && !in.safe &&
                                   Abs(o.reference_pa - o.setpoint_pa) < tol &&
                                   Abs(o.reading.pa) < Abs(o.setpoint_pa) - tol;
    if (HeldFor(short_of_setpoint, m.leak_timing, m.leak_since, in.now_us,
                settings.leak_timeout_us)) {
      raise(Fault::kLeak, slot);
    }
  }

  // The supervisor owns the vacuum pump: on only while a vacuum line needs it, never forever.
  if (pump_wanted && !s.pump_on) s.pump_on_since = in.now_us;
  s.pump_on = pump_wanted;
  if (s.pump_on && in.now_us - s.pump_on_since > settings.pump_max_run_us) {
    raise(Fault::kPumpRunTime, static_cast<int32_t>((in.now_us - s.pump_on_since) / 1000000));
  }

  s.active = active;
  for (uint8_t f = 0; active != 0 && f < static_cast<uint8_t>(Fault::kCount); ++f) {
    if ((active & FaultBit(static_cast<Fault>(f))) != 0)
      LatchFault(s, static_cast<Fault>(f), in.now_us, detail[f]);
  }
  if (s.latched != 0) s.pump_on = false;
  return s.latched & ~before;
}

protocol::Status ClearFaults(SupervisorState& s, uint32_t mask) {
  if ((s.latched & s.active & mask) != 0) return protocol::Status::kConditionPersists;
  s.latched &= ~mask;
  for (LineMonitor& m : s.lines) {
    m.implausible_timing = false;
    m.leak_timing = false;
  }
  return protocol::Status::kOk;
}

uint8_t FaultHistory(const SupervisorState& s, protocol::FaultRecord* out) {
  const uint8_t start = static_cast<uint8_t>(
      (s.history_next + protocol::kMaxFaultRecords - s.history_count) % protocol::kMaxFaultRecords);
  for (uint8_t i = 0; i < s.history_count; ++i)
    out[i] = s.history[(start + i) % protocol::kMaxFaultRecords];
  return s.history_count;
}

}  // namespace palpa::core
