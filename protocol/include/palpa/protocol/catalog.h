// The message catalog: every message type in one list, its lookup table and its hash.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "palpa/protocol/faults.h"
#include "palpa/protocol/field_codec.h"
#include "palpa/protocol/messages_admin.h"
#include "palpa/protocol/messages_bootstrap.h"
#include "palpa/protocol/messages_config.h"
#include "palpa/protocol/messages_report.h"
#include "palpa/protocol/messages_session.h"
#include "palpa/protocol/messages_stream.h"
#include "palpa/protocol/messages_update.h"
#include "palpa/protocol/wire.h"

namespace palpa::protocol {

template <class... Messages>
struct MessageList {
  static constexpr size_t kSize = sizeof...(Messages);
};

/// The one list of messages. Adding one here gives it a codec, a dispatch entry, a hash
/// contribution (unless bootstrap) and a documentation row.
using Catalog =
    MessageList<Hello, HelloReply, Ack, Nack, EStop, UpdateEnter, UpdateErase, UpdateWrite,
                UpdateQuery, UpdateStatus, UpdateActivate, UpdateReboot, UpdateConfirm, SlotsQuery,
                SlotsReport, Heartbeat, SetLineSetpoints, SetFingerTargets, SetFingerMode, Close,
                Release, ConfigureLine, ConfigureFinger, ConfigureBoard, StagedBegin, StagedPart,
                StagedCommit, GetConfig, ConfigReport, SaveConfig, FactoryReset, ClearFault,
                Telemetry, GetLoopStats, LoopStats, GetDiagnostics, Diagnostics>;

/// Calls f.template operator()<M>() for every message M of the list, in order.
template <class F, class... Messages>
constexpr void ForEachMessage(MessageList<Messages...>, F&& f) {
  (f.template operator()<Messages>(), ...);
}

/// FNV-1a over a canonical description of fields: names, wire types, ranges, enumerators.
class CatalogHasher {
 public:
  constexpr void Byte(uint8_t b) { hash_ = (hash_ ^ b) * 16777619u; }
  constexpr void Str(const char* s) {
    while (*s != '\0') Byte(static_cast<uint8_t>(*s++));
    Byte(0);
  }
  constexpr void Num(uint64_t v) {
    for (int i = 0; i < 8; ++i) Byte(static_cast<uint8_t>(v >> (8 * i)));
  }

  template <typename T>
  constexpr void Field(const char* name, const T& v) {
    Field(name, v, std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max());
  }
  template <typename T>
  constexpr void Field(const char* name, const T&, Bound<T> lo, Bound<T> hi) {
    Str(name);
    Num(sizeof(T));
    Num(std::is_same_v<T, float> ? 2 : std::is_signed_v<T> ? 1 : 0);
    Num(Bits(lo));
    Num(Bits(hi));
  }
  constexpr void Flag(const char* name, const bool&) {
    Str(name);
    Str("flag");
  }
  template <typename E>
  constexpr void Enum(const char* name, const E&) {
    Str(name);
    Str("enum");
    Num(sizeof(E));
    const char* const* names = EnumNames(E{});
    for (uint64_t i = 0; i < EnumCount<E>(); ++i) Str(names[i]);
  }
  template <typename T, size_t N>
  constexpr void Array(const char* name, const std::array<T, N>& items, const uint8_t&) {
    Str(name);
    Str("array");
    Num(N);
    if constexpr (std::is_arithmetic_v<T>) {
      Field("item", items[0]);
    } else {
      T::Fields(*this, items[0]);
    }
    Str("end");
  }
  template <size_t N>
  constexpr void Bytes(const char* name, const std::array<uint8_t, N>&, const uint8_t&) {
    Str(name);
    Str("bytes");
    Num(N);
  }
  template <size_t N>
  constexpr void Fixed(const char* name, const std::array<uint8_t, N>&) {
    Str(name);
    Str("fixed");
    Num(N);
  }
  template <size_t N>
  constexpr void Text(const char* name, const std::array<char, N>&) {
    Str(name);
    Str("text");
    Num(N);
  }

  constexpr uint32_t value() const { return hash_; }

 private:
  template <typename T>
  static constexpr uint64_t Bits(T v) {
    if constexpr (std::is_same_v<T, float>) {
      return std::bit_cast<uint32_t>(v);
    } else {
      return static_cast<uint64_t>(v);
    }
  }
  uint32_t hash_ = 2166136261u;
};

/// Names of the bits in order, bit 0 first.
struct BitNames {
  const char* const* names;
  size_t count;
};
inline constexpr BitNames kFaultBitNames{kFaultNames, sizeof(kFaultNames) / sizeof(kFaultNames[0])};
inline constexpr BitNames kLineStatusBitNames{
    kLineStatusNames, sizeof(kLineStatusNames) / sizeof(kLineStatusNames[0])};

/// Hash of every non-bootstrap message of `list`, and of the names of the fault and line-status
/// bits those messages carry (a renumbered bit changes what a field means). Two builds
/// interoperate beyond the bootstrap set only when their hashes match.
template <class List>
constexpr uint32_t ComputeCatalogHash(List list, BitNames faults = kFaultBitNames,
                                      BitNames line_status = kLineStatusBitNames) {
  CatalogHasher h;
  h.Str("palpa-catalog");
  h.Num(kMaxBodySize);
  for (const BitNames& bits : {faults, line_status}) {
    h.Num(bits.count);
    for (size_t i = 0; i < bits.count; ++i) h.Str(bits.names[i]);
  }
  ForEachMessage(list, [&h]<class M>() {
    if (IsBootstrap(static_cast<uint8_t>(M::kInfo.type))) return;
    h.Num(static_cast<uint8_t>(M::kInfo.type));
    h.Str(M::kInfo.name);
    h.Num(static_cast<uint8_t>(M::kInfo.sender));
    h.Num(static_cast<uint8_t>(M::kInfo.delivery));
    M m{};
    M::Fields(h, m);
    h.Str(";");
  });
  return h.value();
}

inline constexpr uint32_t kCatalogHash = ComputeCatalogHash(Catalog{});

/// Metadata of a type id, or nullptr for an unknown type.
const MessageInfo* FindMessageInfo(uint8_t type);

}  // namespace palpa::protocol
