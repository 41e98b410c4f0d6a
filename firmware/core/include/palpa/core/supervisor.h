// The supervisor: one latched fault bitmap, one shutdown path. Pure: observations in, faults out.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/core/line_pipeline.h"
#include "palpa/protocol/faults.h"
#include "palpa/protocol/messages_config.h"
#include "palpa/protocol/messages_report.h"
#include "palpa/protocol/status.h"

namespace palpa::core {

struct SupervisorSettings {
  uint64_t host_timeout_us = 100000;
  uint64_t leak_timeout_us = 5000000;
  uint64_t pump_max_run_us = 600000000;
  uint64_t sensor_window_us = 3000000;
  float tolerance_pa = 5000;
};

SupervisorSettings MakeSupervisorSettings(const protocol::ConfigureBoard& board);

/// What the tick saw on one line.
struct LineObservation {
  bool configured = false;
  bool has_sensor = false;
  LineReading reading;      ///< this tick's sensor reading
  uint32_t raw_counts = 0;  ///< this tick's ADC counts (looked at only while the reading is valid)
  /// Readings below or above these are over-limit: the line's limits widened by the sensor
  /// tolerance (fixed per configuration, so not recomputed every tick).
  float alarm_below_pa = 0, alarm_above_pa = 0;
  // The slow monitors' view, filled by the board for the line they visit this tick (SlowSlot):
  // where the last tick left the line.
  bool closed_loop = false;  ///< commanded pressure with the trim on (outside safe)
  float reference_pa = 0;    ///< regulator-model output
  float setpoint_pa = 0;
};

/// The sensing stage's summary of a tick's readings, built line by line with NoteReading where
/// each reading is converted, so the supervisor judges every line every tick without visiting
/// them all again.
struct ReadingSummary {
  uint8_t first_invalid = protocol::kNoLine;  ///< first line whose sensor read no pressure
  uint8_t first_beyond = protocol::kNoLine;   ///< first line reading beyond its alarm bounds
  float beyond_pa = 0;                        ///< that line's reading
};

/// Adds line `line`'s reading, `reading` as just converted (a line with a sensor; lines in
/// increasing order; `o` for its alarm bounds).
inline void NoteReading(ReadingSummary& summary, uint8_t line, LineReading reading,
                        const LineObservation& o) {
  if (!reading.valid) {
    if (summary.first_invalid == protocol::kNoLine) summary.first_invalid = line;
  } else if (reading.pa > o.alarm_above_pa || reading.pa < o.alarm_below_pa) {
    if (summary.first_beyond == protocol::kNoLine) {
      summary.first_beyond = line;
      summary.beyond_pa = reading.pa;
    }
  }
}

/// SupervisorInput::failed_output when every output took its write.
inline constexpr int32_t kNoFailedOutput = -1;

struct SupervisorInput {
  uint64_t now_us = 0;
  bool session_open = false;
  uint64_t last_host_frame_us = 0;  ///< the session's last fresh frame (Hello included)
  /// Something was applied since the session's Hello, the last clear or release: the outputs
  /// are out of their safe state on this host's behalf (a jamming finger's bias included).
  bool actuating = false;
  bool estop_pin = false;
  bool config_intact = true;   ///< the periodic CRC of the live configuration matched
  bool safe = false;           ///< outputs are in the safe state this tick
  bool vacuum_demand = false;  ///< a line commanded vacuum beyond its regulator's minimum
  /// The first output whose last write failed (output_write's detail, protocol::OutputKind), or
  /// kNoFailedOutput.
  int32_t failed_output = kNoFailedOutput;
  ReadingSummary readings;  ///< every sensor line's reading this tick
  std::array<LineObservation, protocol::kMaxLines> lines{};
};

struct LineMonitor {
  uint64_t implausible_since = 0;
  uint64_t leak_since = 0;
  uint64_t stuck_since = 0;
  uint32_t stuck_counts = 0;
  float stuck_reference = 0;
  bool implausible_timing = false;
  bool leak_timing = false;
};

struct SupervisorState {
  uint32_t latched = 0;  ///< faults latched until ClearFault
  uint32_t active = 0;   ///< conditions present now
  std::array<LineMonitor, protocol::kMaxLines> lines{};
  uint8_t slow_slot = 0;  ///< the line slot the slow monitors visit this tick
  bool pump_on = false;
  /// The session's host was silent beyond the timeout at the last Supervise: the board ends the
  /// session (a fault only if it was actuating).
  bool host_silent = false;
  uint64_t pump_on_since = 0;
  std::array<protocol::FaultRecord, protocol::kMaxFaultRecords> history{};  ///< ring
  uint8_t history_count = 0;
  uint8_t history_next = 0;
};

/// The line slot the slow monitors (implausible against the model, stuck, leak) visit at the
/// next Supervise: one a tick, each slot every kMaxLines ticks.
inline uint8_t SlowSlot(const SupervisorState& s) { return s.slow_slot; }

/// The session's host has sent nothing fresh for longer than the timeout: the session is over.
/// It latches host_silence only when the host left the board actuating (Supervise).
inline bool HostSilent(const SupervisorSettings& settings, const SupervisorInput& in) {
  return in.session_open && in.now_us - in.last_host_frame_us > settings.host_timeout_us;
}

/// Latches a fault (and records it) — the single entry into the safe state.
void LatchFault(SupervisorState& s, protocol::Fault fault, uint64_t now_us, int32_t detail);

/// Evaluates every condition for this tick, latches new faults and decides the pump.
/// Returns the bits newly latched.
uint32_t Supervise(const SupervisorSettings& settings, SupervisorState& s,
                   const SupervisorInput& in);

/// ClearFault: refused (kConditionPersists) while any masked fault's condition is still present.
protocol::Status ClearFaults(SupervisorState& s, uint32_t mask);

/// Copies the history ring oldest-first.
uint8_t FaultHistory(const SupervisorState& s, protocol::FaultRecord* out);

}  // namespace palpa::core
