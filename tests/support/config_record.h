// One Configure* message as a configuration record (protocol/config_records.h), for tests that
// build staged blobs by hand.
#pragma once

#include <cstdint>
#include <vector>

#include "palpa/protocol/config_records.h"

namespace palpa::testing {

/// The record's bytes, header included; empty when the message does not encode.
template <class M>
std::vector<uint8_t> ConfigRecord(const M& message) {
  std::vector<uint8_t> record(protocol::kRecordHeaderSize + 512);
  const auto size = protocol::EncodeRecord(message, record.data(), record.size());
  record.resize(size.ok() ? size.value : 0);
  return record;
}

/// Appends the message's record to a blob; false when it does not encode.
template <class M>
bool AppendConfigRecord(std::vector<uint8_t>& blob, const M& message) {
  const std::vector<uint8_t> record = ConfigRecord(message);
  blob.insert(blob.end(), record.begin(), record.end());
  return !record.empty();
}

}  // namespace palpa::testing
