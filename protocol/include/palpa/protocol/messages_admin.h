// Staged configuration, configuration read-back, persistence and fault clearing.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::protocol {

/// Staged blob = a sequence of records [u16 body length][u8 type][body], each a Configure*
/// message; validated as a whole and applied atomically between ticks on commit.
struct StagedBegin {
  static constexpr MessageInfo kInfo{MessageType::kStagedBegin, "StagedBegin", Sender::kHost,
                                     Delivery::kReliable,
                                     "start a staged configuration of total_bytes"};
  uint16_t total_bytes = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("total_bytes", m.total_bytes, 1, kMaxStagedBytes);
  }
};

struct StagedPart {
  static constexpr MessageInfo kInfo{MessageType::kStagedPart, "StagedPart", Sender::kHost,
                                     Delivery::kReliable, "bytes of the staged blob at offset"};
  uint16_t offset = 0;
  uint8_t data_size = 0;
  std::array<uint8_t, kMaxStagedChunk> data{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("offset", m.offset, 0, kMaxStagedBytes - 1);
    v.Bytes("data", m.data, m.data_size);
  }
};

struct StagedCommit {
  static constexpr MessageInfo kInfo{MessageType::kStagedCommit, "StagedCommit", Sender::kHost,
                                     Delivery::kReliable,
                                     "check CRC, validate every record, apply all or nothing"};
  uint16_t total_bytes = 0;
  uint32_t crc32 = 0;  ///< CRC-32 of the whole blob
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("total_bytes", m.total_bytes, 1, kMaxStagedBytes);
    v.Field("crc32", m.crc32);
  }
};

struct GetConfig {
  static constexpr MessageInfo kInfo{MessageType::kGetConfig, "GetConfig", Sender::kHost,
                                     Delivery::kReliable,
                                     "read one section back, answered by ConfigReport"};
  ConfigSection section = ConfigSection::kBoard;
  uint8_t index = 0;
  uint16_t offset = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Enum("section", m.section);
    v.Field("index", m.index, 0, kMaxLines - 1);
    v.Field("offset", m.offset, 0, kMaxStagedBytes - 1);
  }
};

struct ConfigReport {
  static constexpr MessageInfo kInfo{
      MessageType::kConfigReport, "ConfigReport", Sender::kBoard, Delivery::kResponse,
      "a chunk of the section's Configure* body, plus the CRC of the whole live configuration"};
  uint32_t boot_nonce = 0;
  ConfigSection section = ConfigSection::kBoard;
  uint8_t index = 0;
  uint32_t config_crc = 0;
  uint16_t total_bytes = 0;
  uint16_t offset = 0;
  uint8_t data_size = 0;
  std::array<uint8_t, kMaxConfigChunk> data{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("boot_nonce", m.boot_nonce);
    v.Enum("section", m.section);
    v.Field("index", m.index, 0, kMaxLines - 1);
    v.Field("config_crc", m.config_crc);
    v.Field("total_bytes", m.total_bytes, 0, kMaxStagedBytes);
    v.Field("offset", m.offset, 0, kMaxStagedBytes);
    v.Bytes("data", m.data, m.data_size);
  }
};

struct SaveConfig {
  static constexpr MessageInfo kInfo{MessageType::kSaveConfig, "SaveConfig", Sender::kHost,
                                     Delivery::kReliable,
                                     "persist the live configuration (two copies with CRC)"};
  template <class V, class M>
  static constexpr void Fields(V&, M&) {}
};

struct FactoryReset {
  static constexpr MessageInfo kInfo{MessageType::kFactoryReset, "FactoryReset", Sender::kHost,
                                     Delivery::kReliable,
                                     "erase the saved configuration; back to compiled defaults"};
  uint32_t confirm = kFactoryResetMagic;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("confirm", m.confirm, kFactoryResetMagic, kFactoryResetMagic);
  }
};

struct ClearFault {
  static constexpr MessageInfo kInfo{MessageType::kClearFault, "ClearFault", Sender::kHost,
                                     Delivery::kReliable,
                                     "unlatch faults whose cause is gone; outputs stay safe"};
  uint32_t mask = 0xFFFFFFFFu;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("mask", m.mask);
  }
};

}  // namespace palpa::protocol
