// Ending the command line on SIGINT, SIGTERM or SIGHUP without leaving a board actuated: the
// session of every open device is closed (Close: outputs safe at once, no fault) before palpa
// exits, whatever the command was doing.
#pragma once

#include "palpa/host/device.h"

namespace palpa::cli {

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread — and so in every thread started after
/// it — and starts the thread that waits for them. Call first in main, before any other thread.
void StartSignalWatch();

/// A signal has arrived. Commands that wait (monitor, record, set and line with --hold) poll this
/// and return normally, which closes their sessions on the way out.
bool Interrupted();

/// While one lives, the running command polls Interrupted(): a signal gives it a moment to end by
/// itself before the sessions are closed for it.
class PollsInterruption {
 public:
  PollsInterruption();
  ~PollsInterruption();
  PollsInterruption(const PollsInterruption&) = delete;
  PollsInterruption& operator=(const PollsInterruption&) = delete;
};

/// While one lives, a signal closes `device`'s session before palpa exits.
class ClosedOnSignal {
 public:
  explicit ClosedOnSignal(host::Device* device);
  ~ClosedOnSignal();
  ClosedOnSignal(const ClosedOnSignal&) = delete;
  ClosedOnSignal& operator=(const ClosedOnSignal&) = delete;

 private:
  host::Device* device_;
};

}  // namespace palpa::cli
