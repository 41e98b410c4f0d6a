// The C ABI's device handle, shared by the files that implement palpa.h (internal).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "palpa/c/palpa.h"
#include "palpa/host/device.h"
#include "palpa/host/served_device.h"

/// Either a board this process opened (`device`) or one behind palpa serve (`served`).
struct palpa_device {
  std::unique_ptr<palpa::host::Device> device;
  std::string error;
  uint32_t faults = 0;  ///< of the last failed call
  mutable std::mutex mutex;
  std::condition_variable arrived;
  std::deque<palpa_sample> samples;
  uint64_t dropped = 0;
  int subscription = 0;
  std::vector<palpa::host::FingerCurves>
      curves;  ///< for the samples' finger outputs, taken on opening
  /// Last, so it goes first: its reader thread queues samples under `mutex` until it is joined.
  std::unique_ptr<palpa::host::ServedDevice> served;
};

namespace palpa::c_api {

/// A failed outcome's message and faults kept on the handle (palpa_last_error, palpa_last_faults);
/// its status as the C code.
inline int Report(palpa_device* d, const host::Outcome& o) {
  if (!o.ok()) {
    d->error = o.message;
    d->faults = o.faults;
  }
  return static_cast<int>(o.status);
}

/// `s` at the queue's end, the oldest dropped (and counted) when it is full; d->mutex held.
void QueueSample(palpa_device* d, const palpa_sample& s);

/// A device behind palpa serve (uri "serve:..."), its telemetry queued from the start.
host::Result<palpa_device*> OpenServed(const std::string& uri);

/// A call the server's API does not offer, on a served device: unsupported, saying so.
inline int NotThroughServe(palpa_device* d, const char* function) {
  d->error = std::string(function) + ": not available through palpa serve (" + d->served->uri() +
             "): open the board where it is attached to use it";
  d->faults = 0;
  return static_cast<int>(protocol::Status::kUnsupported);
}

}  // namespace palpa::c_api
