// Fault bits of the supervisor's latched bitmap, as carried in telemetry and Diagnostics.
#pragma once

#include <cstdint>

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
  kOutputWrite = 9,        ///< a DAC code could not be written
  kCount
};

inline constexpr const char* const kFaultNames[] = {
    "host_silence", "over_limit",    "implausible_sensor", "config_crc",    "unexpected_reset",
    "leak",         "estop_command", "estop_pin",          "pump_run_time", "output_write"};
static_assert(sizeof(kFaultNames) / sizeof(kFaultNames[0]) == static_cast<unsigned>(Fault::kCount));

constexpr uint32_t FaultBit(Fault f) { return 1u << static_cast<uint8_t>(f); }
inline constexpr uint32_t kAllFaults = (1u << static_cast<uint8_t>(Fault::kCount)) - 1u;

}  // namespace palpa::protocol
