// The board's methods as the API offers them: info, diagnostics, configuration, targets in every
// unit, raw lines, E-stop, clear and release. Each reads and checks its parameters first (nothing
// is sent on a bad one), then becomes a job the board worker runs against the device.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "palpa/host/device.h"
#include "palpa/serve/json_rpc.h"

namespace palpa::serve {

/// What a board job produced: a result, or the error for the caller.
struct BoardAnswer {
  rpc::Json result;
  std::optional<rpc::Error> error;
};
using BoardJob = std::function<BoardAnswer(host::Device&)>;

/// A checked call ready to run, or why it was refused. `board`: what the device said at Hello.
struct PreparedCall {
  std::optional<rpc::Error> error;
  BoardJob job;
};
PreparedCall PrepareBoardCall(const std::string& method, const rpc::Json& params,
                              const protocol::HelloReply& board);

/// A refusal by the library or the board as an error: data {"status", "faults", "notes"}.
rpc::Error Refused(const host::Outcome& outcome);

}  // namespace palpa::serve
