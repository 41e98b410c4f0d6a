// Ending a session on purpose: Close (outputs safe, session over) and Release (outputs safe,
// session kept). Catalog messages, not bootstrap: see docs/protocol.md, "Closing a session".
#pragma once

#include <cstdint>

#include "palpa/protocol/message_info.h"

namespace palpa::protocol {

/// Unsequenced like EStop and answered by Ack (boot nonce) — but a deliberate end, not an
/// emergency: no fault is latched. A Close of another session, or with none open, is Nacked
/// no_session; a bootloader Nacks it unsupported. The host repeats it until it hears either.
struct Close {
  static constexpr MessageInfo kInfo{
      MessageType::kClose, "Close", Sender::kHost, Delivery::kUnsequenced,
      "ends the session: every output safe within a tick, no fault latched; answered by Ack"};
  uint32_t session = 0;  ///< host_nonce of the session's Hello
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("session", m.session);
  }
};

struct Release {
  static constexpr MessageInfo kInfo{
      MessageType::kRelease, "Release", Sender::kHost, Delivery::kUnsequenced,
      "every output safe within a tick, no fault latched, session kept; answered by Ack"};
  uint32_t session = 0;  ///< host_nonce of the session's Hello
  template <class V, class M>
  static constexpr void Fields(V& v, M& m) {
    v.Field("session", m.session);
  }
};

}  // namespace palpa::protocol
