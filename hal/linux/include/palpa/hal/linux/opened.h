// What a hal/linux call returns: what it made (a device opened, a file read) or that it is done,
// or a status and the words that say why not.
// The host's Result<T> shape (host/lib's outcome.h) one layer down, where the host library cannot
// be reached (DESIGN §2: the host library stands on this layer, not the other way round).
#pragma once

#include <string>
#include <utility>

#include "palpa/protocol/status.h"

namespace palpa::hal {

using protocol::Status;

template <typename T>
struct Opened {
  protocol::Status status = protocol::Status::kOk;
  std::string message;  ///< empty when opened
  T value{};

  Opened(T v) : value(std::move(v)) {}  // NOLINT: implicit, like host::Result
  Opened(protocol::Status s, std::string why) : status(s), message(std::move(why)) {}
  bool ok() const { return status == protocol::Status::kOk; }
};

/// A call with nothing to give back: done, or a status and the words that say why not.
struct Done {
  protocol::Status status = protocol::Status::kOk;
  std::string message;  ///< empty when done

  Done() = default;
  Done(protocol::Status s, std::string why) : status(s), message(std::move(why)) {}
  bool ok() const { return status == protocol::Status::kOk; }
};

}  // namespace palpa::hal
