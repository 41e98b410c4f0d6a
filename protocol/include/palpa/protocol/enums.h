// Enumerations carried in message fields, each with its wire names (hashed into the catalog).
#pragma once

#include <cstdint>

namespace palpa::protocol {

// Each enum ends with kCount and has an EnumNames() overload found by argument-dependent lookup.
#define PALPA_ENUM_NAMES(Type, ...)                                    \
  inline constexpr const char* const k##Type##Names[] = {__VA_ARGS__}; \
  static_assert(sizeof(k##Type##Names) / sizeof(k##Type##Names[0]) ==  \
                static_cast<unsigned>(Type::kCount));                  \
  constexpr const char* const* EnumNames(Type) { return k##Type##Names; }

enum class MessageType : uint8_t;  // catalog.h lists them

enum class BoardKind : uint8_t { kSim, kMps2An386, kStm32f4, kLinux, kCount };
PALPA_ENUM_NAMES(BoardKind, "sim", "mps2-an386", "stm32f4", "linux")

enum class ResetCause : uint8_t {
  kPowerOn,
  kSoftware,
  kWatchdog,
  kBrownOut,
  kPin,
  kFaultHandler,
  kUpdate,
  kUnknown,
  kCount
};
PALPA_ENUM_NAMES(ResetCause, "power_on", "software", "watchdog", "brown_out", "pin",
                 "fault_handler", "update", "unknown")

/// Regulator class of a line; each class has a compiled-in hard ceiling.
enum class LineKind : uint8_t { kPressure, kVacuum, kBias, kCount };
PALPA_ENUM_NAMES(LineKind, "pressure", "vacuum", "bias")

/// Analogue command signal of a regulator (ITV suffix -2, -3, current versions).
enum class SignalRange : uint8_t { kVolt0To5, kVolt0To10, kMilliamp4To20, kCount };
PALPA_ENUM_NAMES(SignalRange, "0-5V", "0-10V", "4-20mA")

enum class SensorKind : uint8_t { kNone, kAnalog, kCount };
PALPA_ENUM_NAMES(SensorKind, "none", "analog")

enum class FingerKind : uint8_t { kPneumatic, kJamming, kCount };
PALPA_ENUM_NAMES(FingerKind, "pneumatic", "jamming")

enum class FingerMode : uint8_t { kTarget, kRaw, kCount };
PALPA_ENUM_NAMES(FingerMode, "target", "raw")

/// A finger's output unit: deformation for pneumatic fingers, stiffness for jamming fingers.
enum class OutputUnit : uint8_t { kDeformationMicrometre, kStiffnessMilliNewtonPerMm, kCount };
PALPA_ENUM_NAMES(OutputUnit, "um", "mN/mm")

enum class CompensatorKind : uint8_t { kNone, kBranch, kPrandtlIshlinskii, kAsymmetricPi, kCount };
PALPA_ENUM_NAMES(CompensatorKind, "none", "branch", "pi", "api")

enum class ConfigSection : uint8_t { kBoard, kLine, kFinger, kCount };
PALPA_ENUM_NAMES(ConfigSection, "board", "line", "finger")

enum class SlotState : uint8_t { kEmpty, kValid, kTrial, kConfirmed, kInvalid, kCount };
PALPA_ENUM_NAMES(SlotState, "empty", "valid", "trial", "confirmed", "invalid")

#undef PALPA_ENUM_NAMES

inline constexpr uint8_t kMaxLines = 8;
inline constexpr uint8_t kMaxFingers = 8;
inline constexpr uint8_t kNoLine = 0xFF;

/// Wire range of any pressure field (Pa). Per-line limits and hard ceilings are narrower.
inline constexpr int32_t kMinPressurePa = -100000;
inline constexpr int32_t kMaxPressurePa = 100000;

/// Line status bits in telemetry samples.
namespace line_status {
inline constexpr uint8_t kSafe = 1u << 0;         ///< holding its safe value
inline constexpr uint8_t kSlewing = 1u << 1;      ///< slew limiter active
inline constexpr uint8_t kTrimClamped = 1u << 2;  ///< PI trim at its authority
inline constexpr uint8_t kSaturated = 1u << 3;    ///< output clamped to the line limits
inline constexpr uint8_t kOpenLoop = 1u << 4;     ///< no sensor, or below regulator minimum
inline constexpr uint8_t kRaw = 1u << 5;          ///< finger in raw mode
inline constexpr uint8_t kSensorFault = 1u << 6;  ///< implausible reading
inline constexpr uint8_t kShaping = 1u << 7;      ///< a shaped step drives beyond the target
}  // namespace line_status

/// The line status bits' names, bit 0 first: hashed into the catalog (they give the bits meaning).
inline constexpr const char* const kLineStatusNames[] = {
    "safe", "slewing", "trim_clamped", "saturated", "open_loop", "raw", "sensor_fault", "shaping"};
static_assert(sizeof(kLineStatusNames) / sizeof(kLineStatusNames[0]) == 8 &&
              line_status::kShaping == 1u << 7);

}  // namespace palpa::protocol
