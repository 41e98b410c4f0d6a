// The simulated board `palpa sim start` keeps running, and how the commands after it find it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "palpa/host/outcome.h"

namespace palpa::cli {

struct RunningSim {
  int pid = 0;
  std::string uri;      ///< tcp:127.0.0.1:PORT
  std::string config;   ///< board configuration
  std::string flash;    ///< its flash file
  std::string log;      ///< what palpa-sim printed
  std::string started;  ///< UTC, ISO 8601
};

/// Where palpa keeps the running simulator's record and the simulated boards' flash files:
/// $PALPA_STATE_DIR, else $XDG_STATE_HOME/palpa, else ~/.local/state/palpa.
std::string SimStateDir();

/// The simulated board started by `palpa sim start`, if it still runs. A record whose process is
/// gone (or is no longer palpa-sim) is removed and *gone says so.
std::optional<RunningSim> FindRunningSim(std::string* gone = nullptr);

/// Starts palpa-sim in the background with a flash file and records it; unavailable when it does
/// not start (with what it printed), io_error when its record cannot be kept.
host::Result<RunningSim> StartSim(const std::string& config, const std::string& flash,
                                  const std::vector<std::string>& options);

/// Stops it (SIGTERM, then SIGKILL after 5 s) and removes the record; busy when it does not stop.
host::Outcome StopSim(const RunningSim& sim);

}  // namespace palpa::cli
