// The board's host-silence timeout through a session, and the heartbeat period it asks for.
#include "palpa/host/host_timeout.h"

#include <algorithm>

namespace palpa::host {
namespace {

uint32_t OrDefault(uint32_t host_timeout_us) {
  return host_timeout_us == 0 ? kDefaultHostTimeoutUs : host_timeout_us;
}

}  // namespace

double HeartbeatPeriodSeconds(uint32_t host_timeout_us, float time_scale) {
  const double timeout_us = OrDefault(host_timeout_us);
  const double scale = time_scale > 0 ? time_scale : 1.0;
  return std::max(0.001, timeout_us / 1e6 / scale / 4);
}

void HostTimeoutTracker::OnSession(uint32_t host_timeout_us, float time_scale) {
  known_us_ = OrDefault(host_timeout_us);
  time_scale_ = time_scale;
  in_flight_.clear();
  ++changes_;
}

void HostTimeoutTracker::OnSent(uint32_t cookie, uint32_t host_timeout_us) {
  in_flight_[cookie] = host_timeout_us;
  ++changes_;
}

void HostTimeoutTracker::OnApplied(uint32_t cookie) {
  const auto it = in_flight_.find(cookie);
  if (it == in_flight_.end()) return;
  known_us_ = it->second;
  in_flight_.erase(it);
  ++changes_;
}

void HostTimeoutTracker::OnRefused(uint32_t cookie) {
  if (in_flight_.erase(cookie) > 0) ++changes_;
}

void HostTimeoutTracker::OnUnknown(uint32_t cookie) {
  const auto it = in_flight_.find(cookie);
  if (it == in_flight_.end()) return;
  known_us_ = std::min(known_us_, it->second);
  in_flight_.erase(it);
  ++changes_;
}

void HostTimeoutTracker::Set(uint32_t host_timeout_us) {
  known_us_ = OrDefault(host_timeout_us);
  ++changes_;
}

uint32_t HostTimeoutTracker::EffectiveTimeoutUs() const {
  uint32_t shortest = known_us_;
  for (const auto& [cookie, timeout_us] : in_flight_) shortest = std::min(shortest, timeout_us);
  return shortest;
}

double HostTimeoutTracker::HeartbeatPeriodSeconds() const {
  return host::HeartbeatPeriodSeconds(EffectiveTimeoutUs(), time_scale_);
}

}  // namespace palpa::host
