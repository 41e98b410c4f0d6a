// The bootstrap set: session setup, Ack/Nack, EStop and firmware update. Frozen across versions.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"
#include "palpa/protocol/status.h"

namespace palpa::protocol {

// Each message lists its fields once, in wire order, in Fields(); the encoder, decoder, catalog
// hash, documentation and JSON tools all walk that one list.

struct Hello {
  static constexpr MessageInfo kInfo{MessageType::kHello, "Hello", Sender::kHost,
                                     Delivery::kUnsequenced,
                                     "opens a session; resets sequence state on both sides"};
  uint32_t host_nonce = 0;
  uint8_t initial_seq = 0;  ///< first reliable sequence number the host will use
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("host_nonce", m.host_nonce);
    v.Field("initial_seq", m.initial_seq);
  }
};

struct LineSummary {
  LineKind kind = LineKind::kPressure;
  bool has_sensor = false;
  int32_t limit_min_pa = 0;
  int32_t limit_max_pa = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Enum("kind", m.kind);
    v.Flag("has_sensor", m.has_sensor);
    v.Field("limit_min_pa", m.limit_min_pa, kMinPressurePa, kMaxPressurePa);
    v.Field("limit_max_pa", m.limit_max_pa, kMinPressurePa, kMaxPressurePa);
  }
};

struct FingerSummary {
  FingerKind kind = FingerKind::kPneumatic;
  FingerMode mode = FingerMode::kTarget;
  uint8_t line_a = 0;        ///< pressure line (pneumatic) or bias line (jamming)
  uint8_t line_b = kNoLine;  ///< vacuum line (jamming) or 0xFF
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Enum("kind", m.kind);
    v.Enum("mode", m.mode);
    v.Field("line_a", m.line_a, 0, kMaxLines - 1);
    v.Field("line_b", m.line_b);
  }
};

struct HelloReply {
  static constexpr MessageInfo kInfo{MessageType::kHelloReply, "HelloReply", Sender::kBoard,
                                     Delivery::kResponse, "board identity and session start"};
  uint32_t host_nonce = 0;  ///< echoed from Hello
  uint32_t boot_nonce = 0;  ///< random per boot; changes when the board resets
  BoardKind board_kind = BoardKind::kSim;
  uint32_t board_id = 0;
  uint8_t protocol_version = 1;
  uint8_t firmware_major = 0;
  uint8_t firmware_minor = 0;
  uint8_t firmware_patch = 0;
  uint32_t catalog_hash = 0;
  ResetCause reset_cause = ResetCause::kPowerOn;
  bool config_is_default = true;
  bool plant_simulated = false;
  float time_scale = 1.0f;       ///< virtual seconds per wall-clock second (palpa-sim --speed)
  uint16_t rx_buffer_bytes = 0;  ///< host keeps at most this many bytes in flight
  uint8_t active_slot = 0;
  uint32_t rollback_counter = 0;
  uint32_t host_timeout_us = 0;  ///< host-silence timeout in board time
  uint32_t fault_bitmap = 0;
  std::array<char, 24> config_name{};
  uint8_t line_count = 0;
  std::array<LineSummary, kMaxLines> lines{};
  uint8_t finger_count = 0;
  std::array<FingerSummary, kMaxFingers> fingers{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("host_nonce", m.host_nonce);
    v.Field("boot_nonce", m.boot_nonce);
    v.Enum("board_kind", m.board_kind);
    v.Field("board_id", m.board_id);
    v.Field("protocol_version", m.protocol_version);
    v.Field("firmware_major", m.firmware_major);
    v.Field("firmware_minor", m.firmware_minor);
    v.Field("firmware_patch", m.firmware_patch);
    v.Field("catalog_hash", m.catalog_hash);
    v.Enum("reset_cause", m.reset_cause);
    v.Flag("config_is_default", m.config_is_default);
    v.Flag("plant_simulated", m.plant_simulated);
    v.Field("time_scale", m.time_scale, 0.001f, 1000.0f);
    v.Field("rx_buffer_bytes", m.rx_buffer_bytes, 64, 65535);
    v.Field("active_slot", m.active_slot, 0, 1);
    v.Field("rollback_counter", m.rollback_counter);
    v.Field("host_timeout_us", m.host_timeout_us);
    v.Field("fault_bitmap", m.fault_bitmap);
    v.Text("config_name", m.config_name);
    v.Array("lines", m.lines, m.line_count);
    v.Array("fingers", m.fingers, m.finger_count);
  }
};

struct Ack {
  static constexpr MessageInfo kInfo{MessageType::kAck, "Ack", Sender::kBoard, Delivery::kResponse,
                                     "command applied; header seq acks cumulatively"};
  uint32_t boot_nonce = 0;
  uint8_t acked_type = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("acked_type", m.acked_type);
  }
};

struct Nack {
  static constexpr MessageInfo kInfo{
      MessageType::kNack, "Nack", Sender::kBoard, Delivery::kResponse,
      "command refused (consumes its seq); seq_gap asks for retransmission from detail"};
  uint32_t boot_nonce = 0;
  uint8_t refused_type = 0;
  Status status = Status::kOk;
  uint32_t detail = 0;  ///< seq_gap: expected seq; stale: applied generation; else an index
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("refused_type", m.refused_type);
    v.Enum("status", m.status);
    v.Field("detail", m.detail);
  }
};

struct EStop {
  static constexpr MessageInfo kInfo{MessageType::kEStop, "EStop", Sender::kHost,
                                     Delivery::kUnsequenced,
                                     "every line to its safe value at once; answered by Ack"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

}  // namespace palpa::protocol
