// Board reports: batched telemetry, loop statistics and diagnostics.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"

namespace palpa::protocol {

inline constexpr uint8_t kMaxTelemetrySamples = 19;  ///< line samples per frame (ticks × lines)
inline constexpr uint8_t kMaxFaultRecords = 16;

struct LineSample {
  int32_t setpoint_pa = 0;
  int32_t measured_pa = 0;      ///< sensor reading; 0 without a sensor
  uint16_t command_counts = 0;  ///< DAC counts written
  uint8_t status = 0;           ///< line_status bits
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("setpoint_pa", m.setpoint_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("measured_pa", m.measured_pa, -200000, 200000);
    v.Field("command_counts", m.command_counts);
    v.Field("status", m.status);
  }
};

struct Telemetry {
  static constexpr MessageInfo kInfo{MessageType::kTelemetry, "Telemetry", Sender::kBoard,
                                     Delivery::kBoardStream,
                                     "tick_count ticks × line_count lines, oldest first"};
  uint32_t boot_nonce = 0;
  uint64_t first_sample_us = 0;  ///< board time of the first tick in the batch
  uint32_t sample_interval_us = 0;
  uint8_t tick_count = 0;
  uint8_t line_count = 0;
  uint32_t setpoint_generation = 0;  ///< last SetLineSetpoints applied
  uint32_t target_generation = 0;    ///< last SetFingerTargets applied
  uint32_t fault_bitmap = 0;         ///< latched faults
  uint32_t dropped_frames = 0;       ///< telemetry frames dropped under back-pressure
  uint8_t sample_count = 0;
  std::array<LineSample, kMaxTelemetrySamples> samples{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("first_sample_us", m.first_sample_us);
    v.Field("sample_interval_us", m.sample_interval_us);
    v.Field("tick_count", m.tick_count, 1, kMaxTelemetrySamples);
    v.Field("line_count", m.line_count, 0, kMaxLines);
    v.Field("setpoint_generation", m.setpoint_generation);
    v.Field("target_generation", m.target_generation);
    v.Field("fault_bitmap", m.fault_bitmap);
    v.Field("dropped_frames", m.dropped_frames);
    v.Array("samples", m.samples, m.sample_count);
  }
  /// Cross-field rule: one sample per line per tick.
  static constexpr const char* Check(const Telemetry& m) {
    return m.sample_count == m.tick_count * m.line_count ? nullptr : "sample_count";
  }
};

struct GetLoopStats {
  static constexpr MessageInfo kInfo{MessageType::kGetLoopStats, "GetLoopStats", Sender::kHost,
                                     Delivery::kReliable, "answered by LoopStats"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

struct LoopStats {
  static constexpr MessageInfo kInfo{MessageType::kLoopStats, "LoopStats", Sender::kBoard,
                                     Delivery::kResponse, "control-loop timing since boot"};
  uint32_t boot_nonce = 0;
  uint64_t ticks = 0;
  uint32_t period_us = 0;
  uint32_t jitter_max_us = 0;  ///< largest |start - deadline|
  uint32_t worst_tick_us = 0;
  uint32_t mean_tick_us = 0;
  uint32_t overruns = 0;  ///< deadlines missed
  uint32_t telemetry_dropped = 0;
  uint32_t rx_frames = 0;
  uint32_t rx_errors = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("ticks", m.ticks);
    v.Field("period_us", m.period_us);
    v.Field("jitter_max_us", m.jitter_max_us);
    v.Field("worst_tick_us", m.worst_tick_us);
    v.Field("mean_tick_us", m.mean_tick_us);
    v.Field("overruns", m.overruns);
    v.Field("telemetry_dropped", m.telemetry_dropped);
    v.Field("rx_frames", m.rx_frames);
    v.Field("rx_errors", m.rx_errors);
  }
};

struct GetDiagnostics {
  static constexpr MessageInfo kInfo{MessageType::kGetDiagnostics, "GetDiagnostics", Sender::kHost,
                                     Delivery::kReliable, "answered by Diagnostics"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

struct FaultRecord {
  uint64_t time_us = 0;
  uint8_t fault = 0;   ///< Fault enumerator (bit index)
  int32_t detail = 0;  ///< e.g. the line, or the reading in Pa
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("time_us", m.time_us);
    v.Field("fault", m.fault, 0, 31);
    v.Field("detail", m.detail);
  }
};

struct Diagnostics {
  static constexpr MessageInfo kInfo{MessageType::kDiagnostics, "Diagnostics", Sender::kBoard,
                                     Delivery::kResponse,
                                     "reset cause, faults latched and active, whether the "
                                     "configuration is saved, lines whose shaped steps fell "
                                     "back, fault history"};
  uint32_t boot_nonce = 0;
  ResetCause reset_cause = ResetCause::kPowerOn;
  uint32_t boot_count = 0;
  uint32_t fault_bitmap = 0;       ///< latched
  uint32_t active_conditions = 0;  ///< causes present now
  uint64_t uptime_us = 0;
  bool config_saved = false;    ///< a saved configuration is what the next boot loads
  bool config_unsaved = false;  ///< the live configuration differs from what the next boot loads
  /// Bit per line: its shaped steps fell back to unshaped ones (the outlet ran ahead of the
  /// regulator model during a step), until the line is configured again.
  uint8_t shaping_fallback_lines = 0;
  uint8_t history_count = 0;
  std::array<FaultRecord, kMaxFaultRecords> history{};  ///< oldest first
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Enum("reset_cause", m.reset_cause);
    v.Field("boot_count", m.boot_count);
    v.Field("fault_bitmap", m.fault_bitmap);
    v.Field("active_conditions", m.active_conditions);
    v.Field("uptime_us", m.uptime_us);
    v.Flag("config_saved", m.config_saved);
    v.Flag("config_unsaved", m.config_unsaved);
    v.Field("shaping_fallback_lines", m.shaping_fallback_lines);
    v.Array("history", m.history, m.history_count);
  }
};

}  // namespace palpa::protocol
