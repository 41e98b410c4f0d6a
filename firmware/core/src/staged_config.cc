// A staged configuration upload: parts in order, then one commit.
#include "palpa/core/internal/staged_config.h"

#include <cstring>

#include "palpa/protocol/crc32.h"

namespace palpa::core {

Status StagedConfig::Part(const protocol::StagedPart& m, uint32_t& detail) {
  detail = 0;
  if (expected_ == 0) return Status::kUnavailable;
  // Parts arrive in order on the reliable channel; anything else is a host bug.
  detail = received_;
  if (m.offset != received_) return Status::kOutOfRange;
  if (m.data_size > expected_ - received_) return Status::kOutOfRange;
  std::memcpy(bytes_.data() + m.offset, m.data.data(), m.data_size);
  crc_ = protocol::Crc32Update(crc_, m.data.data(), m.data_size);
  received_ = static_cast<uint16_t>(received_ + m.data_size);
  detail = 0;
  return Status::kOk;
}

Status StagedConfig::Commit(const protocol::StagedCommit& m, uint32_t& detail) {
  const uint16_t received = received_;
  const bool complete = expected_ != 0 && received == expected_ && m.total_bytes == received;
  expected_ = received_ = committed_ = 0;  // one commit per begin, whatever happens
  detail = received;
  if (!complete) return Status::kStagedIncomplete;
  detail = 0;
  if (crc_ != m.crc32) return Status::kCrcError;
  committed_ = received;
  return Status::kOk;
}

Status StagedConfig::ApplyTo(BoardConfig& candidate, uint32_t& detail) const {
  ConfigError error;
  const Status status = ApplyConfigBlob(bytes_.data(), committed_, candidate, &error);
  detail = status == Status::kOk ? 0 : error.detail();
  return status;
}

}  // namespace palpa::core
