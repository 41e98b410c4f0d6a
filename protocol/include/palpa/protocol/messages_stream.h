// Latest-wins streams (heartbeat, setpoints, targets) and the finger mode switch.
#pragma once

#include <array>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/message_info.h"

namespace palpa::protocol {

/// Largest finger target in any output unit (10 mm deformation, 1000 N/mm stiffness).
inline constexpr int32_t kMaxFingerTarget = 1000000;

// Every host-to-board stream frame names the session it belongs to: the nonce of the Hello that
// opened it. The board applies (and counts as its host being alive) only frames of its current
// session, so a stale or second host can neither actuate a line nor keep one actuated.

struct Heartbeat {
  static constexpr MessageInfo kInfo{MessageType::kHeartbeat, "Heartbeat", Sender::kHost,
                                     Delivery::kStream,
                                     "keeps the session's host-silence timer from firing"};
  uint32_t session = 0;  ///< host_nonce of the session's Hello
  uint32_t generation = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("session", m.session);
    v.Field("generation", m.generation);
  }
};

struct LineSetpoint {
  uint8_t line = 0;
  int32_t setpoint_pa = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("line", m.line, 0, kMaxLines - 1);
    v.Field("setpoint_pa", m.setpoint_pa, kMinPressurePa, kMaxPressurePa);
  }
};

struct SetLineSetpoints {
  static constexpr MessageInfo kInfo{MessageType::kSetLineSetpoints, "SetLineSetpoints",
                                     Sender::kHost, Delivery::kStream,
                                     "raw setpoints for lines of fingers in raw mode"};
  uint32_t session = 0;  ///< host_nonce of the session's Hello
  uint32_t generation = 0;
  uint8_t entry_count = 0;
  std::array<LineSetpoint, kMaxLines> entries{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("session", m.session);
    v.Field("generation", m.generation);
    v.Array("entries", m.entries, m.entry_count);
  }
};

struct FingerTarget {
  uint8_t finger = 0;
  OutputUnit unit = OutputUnit::kDeformationMicrometre;  ///< must match the finger's kind
  int32_t target = 0;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("finger", m.finger, 0, kMaxFingers - 1);
    v.Enum("unit", m.unit);
    v.Field("target", m.target, 0, kMaxFingerTarget);
  }
};

struct SetFingerTargets {
  static constexpr MessageInfo kInfo{MessageType::kSetFingerTargets, "SetFingerTargets",
                                     Sender::kHost, Delivery::kStream,
                                     "targets in each finger's output unit (target mode)"};
  uint32_t session = 0;  ///< host_nonce of the session's Hello
  uint32_t generation = 0;
  uint8_t entry_count = 0;
  std::array<FingerTarget, kMaxFingers> entries{};
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("session", m.session);
    v.Field("generation", m.generation);
    v.Array("entries", m.entries, m.entry_count);
  }
};

struct SetFingerMode {
  static constexpr MessageInfo kInfo{MessageType::kSetFingerMode, "SetFingerMode", Sender::kHost,
                                     Delivery::kReliable,
                                     "target mode (compensator) or raw mode (line setpoints)"};
  uint8_t finger = 0;
  FingerMode mode = FingerMode::kTarget;
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("finger", m.finger, 0, kMaxFingers - 1);
    v.Enum("mode", m.mode);
  }
};

}  // namespace palpa::protocol
