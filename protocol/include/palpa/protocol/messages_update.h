// Firmware-update messages of the bootstrap set (DESIGN §9): spoken by application and bootloader.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"

namespace palpa::protocol {

inline constexpr uint8_t kMaxUpdateChunk = 240;
using Sha256 = std::array<uint8_t, 32>;

struct UpdateEnter {
  static constexpr MessageInfo kInfo{MessageType::kUpdateEnter, "UpdateEnter", Sender::kHost,
                                     Delivery::kReliable,
                                     "enter update mode; lines go safe first and stay safe"};
  uint8_t slot = 0;
  uint32_t image_size = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
    v.Field("image_size", m.image_size);
  }
};

struct UpdateErase {
  static constexpr MessageInfo kInfo{MessageType::kUpdateErase, "UpdateErase", Sender::kHost,
                                     Delivery::kReliable,
                                     "erase the sectors covering a range of the inactive slot"};
  uint8_t slot = 0;
  uint32_t offset = 0;
  uint32_t length = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
    v.Field("offset", m.offset);
    v.Field("length", m.length);
  }
};

struct UpdateWrite {
  static constexpr MessageInfo kInfo{MessageType::kUpdateWrite, "UpdateWrite", Sender::kHost,
                                     Delivery::kReliable, "program a chunk at an offset"};
  uint8_t slot = 0;
  uint32_t offset = 0;
  uint8_t data_size = 0;
  std::array<uint8_t, kMaxUpdateChunk> data{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
    v.Field("offset", m.offset);
    v.Bytes("data", m.data, m.data_size);
  }
};

struct UpdateQuery {
  static constexpr MessageInfo kInfo{MessageType::kUpdateQuery, "UpdateQuery", Sender::kHost,
                                     Delivery::kReliable,
                                     "ask how much is written and its hash (resume point)"};
  uint8_t slot = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
  }
};

struct UpdateStatus {
  static constexpr MessageInfo kInfo{MessageType::kUpdateStatus, "UpdateStatus", Sender::kBoard,
                                     Delivery::kResponse,
                                     "bytes written contiguously from 0 and their SHA-256"};
  uint32_t boot_nonce = 0;
  uint8_t slot = 0;
  uint32_t written_bytes = 0;
  Sha256 written_sha256{};
  bool in_update_mode = false;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("slot", m.slot, 0, 1);
    v.Field("written_bytes", m.written_bytes);
    v.Fixed("written_sha256", m.written_sha256);
    v.Flag("in_update_mode", m.in_update_mode);
  }
};

struct UpdateActivate {
  static constexpr MessageInfo kInfo{MessageType::kUpdateActivate, "UpdateActivate", Sender::kHost,
                                     Delivery::kReliable,
                                     "verify the written image and mark it for one trial boot"};
  uint8_t slot = 0;
  uint32_t image_size = 0;
  Sha256 image_sha256{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
    v.Field("image_size", m.image_size);
    v.Fixed("image_sha256", m.image_sha256);
  }
};

struct UpdateReboot {
  static constexpr MessageInfo kInfo{MessageType::kUpdateReboot, "UpdateReboot", Sender::kHost,
                                     Delivery::kReliable, "reset the board after the Ack"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

struct UpdateConfirm {
  static constexpr MessageInfo kInfo{MessageType::kUpdateConfirm, "UpdateConfirm", Sender::kHost,
                                     Delivery::kReliable, "make the running trial image permanent"};
  uint8_t slot = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("slot", m.slot, 0, 1);
  }
};

struct SlotsQuery {
  static constexpr MessageInfo kInfo{MessageType::kSlotsQuery, "SlotsQuery", Sender::kHost,
                                     Delivery::kReliable, "ask for both slots' state"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

struct SlotInfo {
  SlotState state = SlotState::kEmpty;
  BoardKind board_kind = BoardKind::kSim;
  uint8_t version_major = 0;
  uint8_t version_minor = 0;
  uint8_t version_patch = 0;
  uint32_t rollback_counter = 0;
  uint32_t image_size = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Enum("state", m.state);
    v.Enum("board_kind", m.board_kind);
    v.Field("version_major", m.version_major);
    v.Field("version_minor", m.version_minor);
    v.Field("version_patch", m.version_patch);
    v.Field("rollback_counter", m.rollback_counter);
    v.Field("image_size", m.image_size);
  }
};

struct SlotsReport {
  static constexpr MessageInfo kInfo{MessageType::kSlotsReport, "SlotsReport", Sender::kBoard,
                                     Delivery::kResponse, "state of both firmware slots"};
  uint32_t boot_nonce = 0;
  uint8_t active_slot = 0;
  uint8_t slot_count = 0;
  std::array<SlotInfo, 2> slots{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Field("active_slot", m.active_slot, 0, 1);
    v.Array("slots", m.slots, m.slot_count);
  }
};

}  // namespace palpa::protocol
