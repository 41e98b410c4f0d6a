// The board's host-silence timeout through a session, and the heartbeat period it asks for.
#include "palpa/host/host_timeout.h"

#include <algorithm>

#include "palpa/protocol/config_records.h"
#include "palpa/protocol/crc32.h"

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

std::optional<uint32_t> CarriedHostTimeout::Carried(uint8_t type, const uint8_t* body,
                                                    size_t size) {
  using protocol::MessageType;
  using protocol::Status;
  switch (static_cast<MessageType>(type)) {
    case MessageType::kConfigureBoard: {
      protocol::ConfigureBoard board;
      if (protocol::DecodeBody(body, size, board) == Status::kOk) return board.host_timeout_us;
      break;
    }
    case MessageType::kStagedBegin: {
      protocol::StagedBegin begin;
      if (protocol::DecodeBody(body, size, begin) == Status::kOk) OnBegin(begin);
      break;
    }
    case MessageType::kStagedPart: {
      protocol::StagedPart part;
      if (protocol::DecodeBody(body, size, part) == Status::kOk) OnPart(part);
      break;
    }
    case MessageType::kStagedCommit: {
      protocol::StagedCommit commit;
      if (protocol::DecodeBody(body, size, commit) == Status::kOk) return OnCommit(commit);
      break;
    }
    default:
      break;
  }
  return std::nullopt;
}

void CarriedHostTimeout::OnBegin(const protocol::StagedBegin& begin) {
  blob_.assign(begin.total_bytes, 0);
}

void CarriedHostTimeout::OnPart(const protocol::StagedPart& part) {
  if (part.offset >= blob_.size()) return;  // the board refuses it too
  const size_t size = std::min<size_t>(part.data_size, blob_.size() - part.offset);
  std::copy(part.data.begin(), part.data.begin() + size, blob_.begin() + part.offset);
}

std::optional<uint32_t> CarriedHostTimeout::OnCommit(const protocol::StagedCommit& commit) const {
  if (commit.total_bytes != blob_.size() ||
      commit.crc32 != protocol::Crc32(blob_.data(), blob_.size())) {
    return std::nullopt;
  }
  // Records as the board reads them; the last board record wins.
  std::optional<uint32_t> carried;
  protocol::RecordReader reader(blob_.data(), blob_.size());
  protocol::Record record;
  while (!reader.done() && reader.Next(record) == protocol::Status::kOk) {
    protocol::ConfigureBoard board;
    if (record.type == static_cast<uint8_t>(protocol::MessageType::kConfigureBoard) &&
        protocol::DecodeBody(record.body, record.size, board) == protocol::Status::kOk) {
      carried = board.host_timeout_us;
    }
  }
  return carried;
}

}  // namespace palpa::host
