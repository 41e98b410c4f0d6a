// palpa-sim's command line.
#pragma once

#include <string>
#include <vector>

#include "palpa/hal/linux/opened.h"
#include "sim_board.h"

namespace palpa::sim {

struct SimCommandLine {
  SimBoardOptions board;
  std::string listen;
  std::string truth;  ///< empty, file:PATH or tcp:HOST:PORT
  uint32_t truth_every_ms = 10;
  float speed = 1.0f;
  /// Latency stamps: "setpoints|targets GENERATION applied|dac MONOTONIC_NS" lines.
  std::string stamp_file;
  std::string rig_modbus;  ///< empty, tcp:HOST:PORT or rtu:PATH: the rig's stage and force sensor
  std::string rig_netft;   ///< empty or udp:HOST:PORT: the rig's force sensor as a Net F/T box
  uint8_t rig_finger = 0;  ///< the finger under the rig's indenter
  /// Addresses other than loopback are refused unless this is set; with it, each one is warned of.
  bool allow_remote = false;
  std::vector<std::string> warnings;  ///< for stderr, before anything is served
  bool help = false;
};

/// Parses argv; a bad argument is refused (kBadValue) with a message naming it and what was
/// expected. Network addresses (--listen, --truth, --rig-modbus, --rig-netft) are IPv4
/// "HOST:PORT", or a PORT alone for 127.0.0.1, and come back in that full form; a host outside
/// 127.0.0.0/8 is refused unless --allow-remote is given, and then it is warned of in `warnings`.
hal::Opened<SimCommandLine> ParseSimCommandLine(const std::vector<std::string>& args);

extern const char* const kSimUsage;

}  // namespace palpa::sim
