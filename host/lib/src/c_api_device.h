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

}  // namespace palpa::c_api
