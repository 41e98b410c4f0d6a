// Methods that act through the device, in groups by prefix — the board's own here (info,
// diagnostics, configuration, targets in every unit, raw lines, E-stop, clear, release), a scene's
// later — each call reading and checking its parameters first (nothing is sent on a bad one), then
// becoming a job the board worker runs against the device.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/serve/json_rpc.h"

namespace palpa::serve {

/// What a board job produced: a result, or the error for the caller.
struct BoardAnswer {
  rpc::Json result;
  std::optional<rpc::Error> error;
};
using BoardJob = std::function<BoardAnswer(host::Device&)>;

/// A checked call ready to run, or why it was refused.
struct PreparedCall {
  std::optional<rpc::Error> error;
  BoardJob job;
  /// Acts on the board: only the controlling client may make it (reading, and stopping, need not).
  bool needs_control = true;
  /// Runs on the urgent lane, never behind a set waiting for the board (E-stop, Release).
  bool urgent = false;
  /// Optional, on the server's thread once the call is allowed: false when a job already queued
  /// will carry this call's effect (a newer sample replacing an older one), so none is queued.
  std::function<bool()> admit = nullptr;
  /// Optional: the caller joins this channel of the group (leaving any other of the group's), and
  /// from then on gets its channel notifications — which go to no other client.
  std::string join = "";
  /// With `join`: the caller hears its channel alone — none of the groups' notifications for
  /// every client (a scene's state) — as a participant's page, which must learn nothing else.
  bool join_alone = false;
};

/// A group of methods sharing a prefix ("board.", "scene."): its names (for server.info, and to
/// tell an unknown method from a known one) and how a call to one of them is prepared.
struct MethodGroup {
  std::string prefix;
  std::vector<std::string> names;
  std::function<PreparedCall(const std::string& method, const rpc::Json& params)> prepare;
  /// Optional, on the server's thread: control changed hands (and the board, if anyone controlled
  /// it, is about to be released) — stop whatever would act on the board again (a scene's feed).
  std::function<void()> on_control_change;
  /// Optional, on the server's thread every few milliseconds: a notification for every client
  /// ({"method", "params"}), or null. Sent as telemetry is: dropped for a client not keeping up.
  std::function<rpc::Json(double now_s)> notification;
  /// Optional, on the server's thread every few milliseconds: the notifications queued since,
  /// each {"channel", "method", "params"}, sent in order to the clients that joined that channel
  /// only, and never dropped (a study's events: each one counts, and one view must not see
  /// another's).
  std::function<std::vector<rpc::Json>()> channel_notifications = nullptr;
  /// Optional: methods only a client in the named channel may call, refused before they are
  /// prepared (a participant's answers come from the participant's view alone).
  std::map<std::string, std::string> channel_only = {};
};

/// The board's methods; `board`: what the device said at Hello.
MethodGroup BoardMethods(const protocol::HelloReply& board);

/// A refusal by the library or the board as an error: data {"status", "faults", "notes"}.
rpc::Error Refused(const host::Outcome& outcome);

}  // namespace palpa::serve
