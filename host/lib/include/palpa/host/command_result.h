// The answer to one reliable command: its status, and the report the board sent with it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"
#include "palpa/protocol/codec.h"

namespace palpa::host {

namespace pp = palpa::protocol;

/// The answer to one reliable command.
struct CommandResult {
  Status status = Status::kOk;
  uint32_t detail = 0;
  uint8_t reply_type = 0;           ///< a report (ConfigReport, Diagnostics, ...) or 0 for Ack/Nack
  std::vector<uint8_t> reply_body;  ///< the report's body
  std::string message;              ///< extra text (versions on a catalog mismatch)
  template <class M>
  bool Reply(M& m) const {
    return reply_type == static_cast<uint8_t>(M::kInfo.type) &&
           pp::DecodeBody(reply_body.data(), reply_body.size(), m) == Status::kOk;
  }
};

}  // namespace palpa::host
