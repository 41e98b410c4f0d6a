// palpa render's --input sources: a recorded trajectory, a pen tablet (evdev), or a tactile array
// over UDP or from a recorded stream — written as URIs the way --device names a board.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/host/outcome.h"

namespace palpa::cli {

struct InputSource {
  enum Kind { kTrajectory, kEvdev, kTactileUdp, kTactileFile } kind = kTrajectory;
  std::string path;  ///< trajectory, evdev node, tactile stream
  std::string host;  ///< tactile-udp: the address to listen on (127.0.0.1 unless named)
  uint16_t port = 0;
};

/// PATH.csv or file:PATH (a trajectory), evdev:/dev/input/eventN, tactile-udp:[HOST:]PORT (on
/// loopback unless HOST names another address, 0.0.0.0 for every one), tactile-file:PATH.csv. A
/// wrong one names what was expected.
host::Result<InputSource> ParseInputSource(const std::string& text);

inline constexpr const char* kInputSyntax =
    "TRAJECTORY.csv | file:TRAJECTORY.csv | evdev:/dev/input/eventN | tactile-udp:[HOST:]PORT | "
    "tactile-file:STREAM.csv";

}  // namespace palpa::cli
