// The host's one error shape: Outcome, a status code with the words that explain it, and
// Result<T>, a value or an Outcome — protocol::Result (status.h, freestanding, the board's) with
// the message a host can afford, as Pigweed's Status and Result with one attached.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "palpa/protocol/status.h"

namespace palpa::host {

using protocol::Status;

/// The outcome of an operation: a shared status code plus words for a person.
struct Outcome {
  Status status = Status::kOk;
  std::string message;
  std::vector<std::string> notes;  ///< e.g. "finger 2: nominal thesis curves (no calibration)"
  /// Refused for latched faults (faulted), or a clear refused while their cause persists
  /// (condition_persists): which ones (fault bits). The message names them, when each latched
  /// (board time) and what to do.
  uint32_t faults = 0;
  bool ok() const { return status == Status::kOk; }
  /// A failure: `status` (never kOk) and what went wrong, in words.
  static Outcome Fail(Status s, std::string why) { return Outcome{s, std::move(why), {}, 0}; }
};

/// A value, or the Outcome that says why there is none (status, message, notes, faults).
template <typename T>
struct Result : Outcome {
  T value{};

  Result(T v) : value(std::move(v)) {}          // NOLINT: implicit, like pw::Result
  Result(Outcome o) : Outcome(std::move(o)) {}  // NOLINT: a failure passed on
  Result(Status s, std::string why) : Outcome{s, std::move(why), {}, 0} {}
  const Outcome& outcome() const { return *this; }
};

}  // namespace palpa::host
