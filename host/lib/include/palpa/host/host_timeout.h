// The board's host-silence timeout as far as the host knows it, and the heartbeat period it asks
// for.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "palpa/protocol/messages_admin.h"
#include "palpa/protocol/messages_config.h"

namespace palpa::host {

/// The timeout a board reports 0 for (a board that does not say) is taken as the protocol's
/// default, so a silent board gets heartbeats at the usual rate rather than as fast as possible.
inline constexpr uint32_t kDefaultHostTimeoutUs = protocol::ConfigureBoard{}.host_timeout_us;

/// A quarter of `host_timeout_us` (board time; 0: the default), in host seconds at `time_scale`
/// board seconds per host second, and never below 1 ms.
double HeartbeatPeriodSeconds(uint32_t host_timeout_us, float time_scale);

/// Follows the timeout through a session: the value the board reported on opening, then every
/// ConfigureBoard the host sends. While one is in flight, and when its outcome is unknown, the
/// shorter of the old and the new value counts: heartbeats are never too slow for either.
class HostTimeoutTracker {
 public:
  /// A new session (HelloReply): the board's value; anything in flight belongs to the old one.
  void OnSession(uint32_t host_timeout_us, float time_scale);
  /// A ConfigureBoard carrying `host_timeout_us` was queued as command `cookie`.
  void OnSent(uint32_t cookie, uint32_t host_timeout_us);
  /// The board applied command `cookie` (Ack).
  void OnApplied(uint32_t cookie);
  /// The board refused command `cookie` (Nack): it changed nothing.
  void OnRefused(uint32_t cookie);
  /// No answer came, or the session ended first: the board may have applied command `cookie`.
  void OnUnknown(uint32_t cookie);
  /// The timeout changed by other means (e.g. read back after a factory reset).
  void Set(uint32_t host_timeout_us);

  /// The timeout heartbeats must satisfy now, board time.
  uint32_t EffectiveTimeoutUs() const;
  double HeartbeatPeriodSeconds() const;
  /// Counts changes, so a heartbeat loop waiting on the old period can wake up for a shorter one.
  uint64_t changes() const { return changes_; }

 private:
  uint32_t known_us_ = kDefaultHostTimeoutUs;
  float time_scale_ = 1.0f;
  std::map<uint32_t, uint32_t> in_flight_;  ///< cookie → timeout it carries
  uint64_t changes_ = 0;
};

/// The host-silence timeout the host's commands carry, for the tracker above: a ConfigureBoard's,
/// and a staged configuration's board record's when its StagedCommit goes out (what is staged is
/// mirrored here), so a staged change that shortens the timeout gets heartbeats to match first.
class CarriedHostTimeout {
 public:
  /// Every reliable command the host queues (type and body): the timeout it carries, if any.
  std::optional<uint32_t> Carried(uint8_t type, const uint8_t* body, size_t size);

 private:
  void OnBegin(const protocol::StagedBegin& begin);
  void OnPart(const protocol::StagedPart& part);
  /// The timeout the committed blob sets, if it holds a board record; none when it holds none or
  /// the commit does not match what was staged (the board refuses such a commit).
  std::optional<uint32_t> OnCommit(const protocol::StagedCommit& commit) const;

  std::vector<uint8_t> blob_;
};

}  // namespace palpa::host
