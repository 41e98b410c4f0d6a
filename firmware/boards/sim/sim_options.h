// palpa-sim's command line.
#pragma once

#include <string>
#include <vector>

#include "sim_board.h"

namespace palpa::sim {

struct SimCommandLine {
  SimBoardOptions board;
  std::string listen;
  std::string truth;  ///< empty, file:PATH or tcp:HOST:PORT
  uint32_t truth_every_ms = 10;
  float speed = 1.0f;
  std::string stamp_file;  ///< latency stamps: "GENERATION applied|dac MONOTONIC_NS" lines
  std::string rig_modbus;  ///< empty, tcp:HOST:PORT or rtu:PATH: the rig's stage and force sensor
  std::string rig_netft;   ///< empty or udp:HOST:PORT: the rig's force sensor as a Net F/T box
  uint8_t rig_finger = 0;  ///< the finger under the rig's indenter
  bool help = false;
};

/// Parses argv; on a bad argument returns false with a message naming it and what was expected.
bool ParseSimCommandLine(const std::vector<std::string>& args, SimCommandLine& out,
                         std::string* error);

extern const char* const kSimUsage;

}  // namespace palpa::sim
