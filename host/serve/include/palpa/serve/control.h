// Who controls the board: one client at a time, the others watch. Control is taken, given up, or
// passed by a user action; a controlling client that goes away (closed, or silent for three
// pings) leaves the board released — and nobody in control, so reconnecting restores nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "palpa/host/outcome.h"

namespace palpa::serve {

using ClientId = uint64_t;

class Control {
 public:
  struct Change {
    bool release_board = false;        ///< send Release (outputs safe, session kept)
    std::optional<ClientId> previous;  ///< who controlled before, if it changed
  };

  std::optional<ClientId> controller() const { return controller_; }
  bool Controls(ClientId id) const { return controller_ == id; }

  /// `id` asks for control. Free: granted. Held by another: refused (kBusy naming the holder)
  /// unless `force` — a person chose to take it — and then the board is released first, so the
  /// new controller starts from a safe board, never from the last one's targets.
  host::Result<Change> Take(ClientId id, bool force, const std::string& holder_name);
  /// `id` gives control up, or goes away: the board is released if it controlled.
  Change Leave(ClientId id);

 private:
  std::optional<ClientId> controller_;
};

/// The server's pings to one client, one every interval. When the next is due, every ping sent
/// since the last one answered is missed; `gone_after` of them means the client is gone (a closed
/// tab, a dead link, a frozen page). A late pong still counts: a slow client is not a gone one.
class PingWatch {
 public:
  explicit PingWatch(int gone_after) : gone_after_(gone_after) {}
  /// The interval elapsed: true when the client is gone; otherwise the sequence number of the ping
  /// to send now in `seq`.
  bool Due(uint64_t& seq) {
    if (missed() >= gone_after_) return true;
    seq = ++sent_;
    return false;
  }
  /// A pong: answers every ping up to `seq` (pongs may be coalesced or lost in between).
  void Pong(uint64_t seq) {
    if (seq > answered_ && seq <= sent_) answered_ = seq;
  }
  int missed() const { return static_cast<int>(sent_ - answered_); }

 private:
  int gone_after_;
  uint64_t sent_ = 0, answered_ = 0;
};

}  // namespace palpa::serve
