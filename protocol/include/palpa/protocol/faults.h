// Fault bits of the supervisor's latched bitmap, as carried in telemetry and Diagnostics.
#pragma once

#include <cstdint>

#include "palpa/protocol/enums.h"

namespace palpa::protocol {

enum class Fault : uint8_t {
  kHostSilence = 0,        ///< the commanding host went silent while the board was actuated
  kOverLimit = 1,          ///< a raw reading beyond the line's limits
  kImplausibleSensor = 2,  ///< sensor disagrees with the regulator model, or stuck
  kConfigCrc = 3,          ///< live configuration no longer matches its CRC
  kUnexpectedReset = 4,    ///< board came up from a watchdog, fault handler or brown-out
  kLeak = 5,               ///< pressure or vacuum not reached in time
  kEStopCommand = 6,       ///< EStop message
  kEStopPin = 7,           ///< E-stop input asserted
  kPumpRunTime = 8,        ///< vacuum pump ran longer than allowed
  kOutputWrite = 9,        ///< an output (DAC code, valve, enable) could not be written
  kCount
};

inline constexpr const char* const kFaultNames[] = {
    "host_silence", "over_limit",    "implausible_sensor", "config_crc",    "unexpected_reset",
    "leak",         "estop_command", "estop_pin",          "pump_run_time", "output_write"};
static_assert(sizeof(kFaultNames) / sizeof(kFaultNames[0]) == static_cast<unsigned>(Fault::kCount));

/// output_write's detail says which output could not be written: bits 0-7 the line (kNoLine for
/// an output every line shares), bits 8-15 what the output is. A DAC channel's detail is its line
/// alone, as before valves and enables were supervised.
enum class OutputKind : uint8_t {
  kDac = 0,           ///< the line's DAC channel: its regulator's command
  kLineValve = 1,     ///< the line's own dump valve driver
  kSupplyEnable = 2,  ///< the supply shut-off's pulsing enable
  kDumpEnable = 3,    ///< the dump valves' pulsing enable
  kPumpEnable = 4,    ///< the vacuum pump's enable
  kCount
};

inline constexpr const char* const kOutputKindNames[] = {"DAC channel", "valve", "supply enable",
                                                         "dump enable", "pump enable"};
static_assert(sizeof(kOutputKindNames) / sizeof(kOutputKindNames[0]) ==
              static_cast<unsigned>(OutputKind::kCount));

constexpr int32_t OutputWriteDetail(OutputKind kind, uint8_t line = kNoLine) {
  return static_cast<int32_t>(static_cast<uint32_t>(kind) << 8 | line);
}

constexpr uint32_t FaultBit(Fault f) { return 1u << static_cast<uint8_t>(f); }
inline constexpr uint32_t kAllFaults = (1u << static_cast<uint8_t>(Fault::kCount)) - 1u;

}  // namespace palpa::protocol
