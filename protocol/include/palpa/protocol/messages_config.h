// Configuration messages: lines, fingers, board settings, staged upload, read-back and persistence.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"

namespace palpa::protocol {

inline constexpr uint8_t kMaxCorrectionPoints = 12;
inline constexpr uint8_t kMaxInversePoints = 16;
inline constexpr uint8_t kMaxCompensatorParams = 80;  ///< over one packet: sent staged
inline constexpr uint16_t kMaxStagedBytes = 4096;
inline constexpr uint8_t kMaxStagedChunk = 249;  // StagedPart fills a packet exactly
inline constexpr uint8_t kMaxConfigChunk = 230;
inline constexpr uint32_t kFactoryResetMagic = 0x52534554;  // "TESR" little-endian: deliberate

/// Regulator static correction: the pressure a command produced, rising and falling.
struct CorrectionPoint {
  int32_t command_pa = 0;
  int32_t rising_pa = 0;
  int32_t falling_pa = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("command_pa", m.command_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("rising_pa", m.rising_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("falling_pa", m.falling_pa, kMinPressurePa, kMaxPressurePa);
  }
};

struct ConfigureLine {
  static constexpr MessageInfo kInfo{
      MessageType::kConfigureLine, "ConfigureLine", Sender::kHost, Delivery::kReliable,
      "scaling, limits, slew, safe value, sensor, PI trim, step shaping, correction"};
  uint8_t line = 0;
  LineKind kind = LineKind::kPressure;
  uint8_t dac_bits = 12;
  SignalRange dac_signal = SignalRange::kVolt0To10;
  int32_t command_min_pa = 0;  ///< pressure at 0 % of the command signal
  int32_t command_max_pa = 0;  ///< pressure at 100 % of the command signal
  int32_t limit_min_pa = 0;
  int32_t limit_max_pa = 0;
  int32_t safe_pa = 0;
  uint32_t slew_pa_per_s = 0;    ///< 0: no slew limit
  int32_t regulator_min_pa = 0;  ///< below this magnitude the command is 0, integrator off
  SensorKind sensor = SensorKind::kNone;
  uint8_t adc_bits = 14;
  int32_t sensor_min_pa = 0;
  int32_t sensor_max_pa = 0;
  uint32_t sensor_counts_min = 0;  ///< ADC counts at sensor_min_pa
  uint32_t sensor_counts_max = 0;  ///< ADC counts at sensor_max_pa
  float trim_kp = 0.0f;
  float trim_ki_per_s = 0.0f;
  int32_t trim_authority_pa = 0;
  int32_t trim_dead_band_pa = 0;
  uint32_t model_tau_us = 0;        ///< regulator-model lag
  uint32_t model_dead_time_us = 0;  ///< regulator-model dead time
  /// The chamber's response to the regulator's command, a lag identified by calibration; 0: not
  /// known, and steps are not shaped.
  uint32_t chamber_tau_us = 0;
  /// How far beyond its target a shaped step may drive the regulator; 0: steps are not shaped.
  int32_t overdrive_pa = 0;
  uint8_t correction_count = 0;
  std::array<CorrectionPoint, kMaxCorrectionPoints> correction{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("line", m.line, 0, kMaxLines - 1);
    v.Enum("kind", m.kind);
    v.Field("dac_bits", m.dac_bits, 8, 16);
    v.Enum("dac_signal", m.dac_signal);
    v.Field("command_min_pa", m.command_min_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("command_max_pa", m.command_max_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("limit_min_pa", m.limit_min_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("limit_max_pa", m.limit_max_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("safe_pa", m.safe_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("slew_pa_per_s", m.slew_pa_per_s, 0u, 100000000u);
    v.Field("regulator_min_pa", m.regulator_min_pa, 0, 10000);
    v.Enum("sensor", m.sensor);
    v.Field("adc_bits", m.adc_bits, 8, 24);
    v.Field("sensor_min_pa", m.sensor_min_pa, -200000, 200000);
    v.Field("sensor_max_pa", m.sensor_max_pa, -200000, 200000);
    v.Field("sensor_counts_min", m.sensor_counts_min, 0u, 16777215u);
    v.Field("sensor_counts_max", m.sensor_counts_max, 0u, 16777215u);
    v.Field("trim_kp", m.trim_kp, 0.0f, 100.0f);
    v.Field("trim_ki_per_s", m.trim_ki_per_s, 0.0f, 1000.0f);
    v.Field("trim_authority_pa", m.trim_authority_pa, 0, 20000);
    v.Field("trim_dead_band_pa", m.trim_dead_band_pa, 0, 5000);
    v.Field("model_tau_us", m.model_tau_us, 0u, 10000000u);
    v.Field("model_dead_time_us", m.model_dead_time_us, 0u, 1000000u);
    v.Field("chamber_tau_us", m.chamber_tau_us, 0u, 10000000u);
    v.Field("overdrive_pa", m.overdrive_pa, 0, 100000);
    v.Array("correction", m.correction, m.correction_count);
  }
};

/// Static inverse: output unit → line setpoint, monotone.
struct InversePoint {
  int32_t output = 0;
  int32_t setpoint_pa = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("output", m.output, 0, 1000000);
    v.Field("setpoint_pa", m.setpoint_pa, kMinPressurePa, kMaxPressurePa);
  }
};

struct ConfigureFinger {
  static constexpr MessageInfo kInfo{MessageType::kConfigureFinger, "ConfigureFinger",
                                     Sender::kHost, Delivery::kReliable,
                                     "line map, kind, static inverse, compensator and parameters"};
  uint8_t finger = 0;
  FingerKind kind = FingerKind::kPneumatic;
  uint8_t line_a = 0;        ///< pressure line (pneumatic) or bias line (jamming)
  uint8_t line_b = kNoLine;  ///< vacuum line (jamming)
  int32_t bias_pa = 0;       ///< jamming: bias held on line_a in target mode
  std::array<char, 12> actuator_serial{};
  uint8_t inverse_count = 0;
  std::array<InversePoint, kMaxInversePoints> inverse{};
  CompensatorKind compensator = CompensatorKind::kNone;
  uint8_t param_count = 0;
  std::array<float, kMaxCompensatorParams> params{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("finger", m.finger, 0, kMaxFingers - 1);
    v.Enum("kind", m.kind);
    v.Field("line_a", m.line_a, 0, kMaxLines - 1);
    v.Field("line_b", m.line_b);
    v.Field("bias_pa", m.bias_pa, 0, kMaxPressurePa);
    v.Text("actuator_serial", m.actuator_serial);
    v.Array("inverse", m.inverse, m.inverse_count);
    v.Enum("compensator", m.compensator);
    v.Array("params", m.params, m.param_count);
  }
};

struct ConfigureBoard {
  static constexpr MessageInfo kInfo{
      MessageType::kConfigureBoard, "ConfigureBoard", Sender::kHost, Delivery::kReliable,
      "name, host-silence timeout, telemetry rate and batching, monitors, homing"};
  std::array<char, 24> config_name{};
  uint32_t host_timeout_us = 100000;
  uint16_t telemetry_decimation = 1;  ///< one sample every N ticks
  uint8_t telemetry_batch = 2;        ///< samples per telemetry frame
  uint16_t config_check_period_ms = 100;
  uint32_t leak_timeout_ms = 5000;
  uint32_t pump_max_run_ms = 600000;
  uint16_t sensor_window_ms = 2000;  ///< implausible-sensor comparison window
  int32_t sensor_tolerance_pa = 5000;
  uint16_t home_dwell_ms = 300;  ///< vented / released time before a compensator re-homes
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Text("config_name", m.config_name);
    v.Field("host_timeout_us", m.host_timeout_us, 10000u, 10000000u);
    v.Field("telemetry_decimation", m.telemetry_decimation, 1, 1000);
    v.Field("telemetry_batch", m.telemetry_batch, 1, 16);
    v.Field("config_check_period_ms", m.config_check_period_ms, 1, 60000);
    v.Field("leak_timeout_ms", m.leak_timeout_ms, 100u, 600000u);
    v.Field("pump_max_run_ms", m.pump_max_run_ms, 1000u, 3600000u);
    v.Field("sensor_window_ms", m.sensor_window_ms, 100, 60000);
    v.Field("sensor_tolerance_pa", m.sensor_tolerance_pa, 100, 100000);
    v.Field("home_dwell_ms", m.home_dwell_ms, 0, 10000);
  }
};

}  // namespace palpa::protocol
