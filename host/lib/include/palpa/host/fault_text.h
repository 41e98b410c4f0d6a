// Latched faults in words a person can act on: their names, what each means, when it latched,
// what to do.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/protocol/messages_report.h"

namespace palpa::host {

/// One fault id in words: "leak"; an id this build has no name for (a newer board) as "fault_N".
std::string FaultName(uint8_t fault);

/// A latched-fault bitmap in words: "host_silence, leak", or "none"; a bit this build has no
/// name for (a newer board) as "fault_N".
std::string FaultNames(uint32_t bitmap);

/// What to do about a latched fault, e.g. for estop_pin "release the E-stop input".
std::string FaultRemedy(uint8_t fault);

/// "host_silence, latched at board time 12.345 s: the host commanding the board went silent while
/// it was actuated — nothing to repair; leak, ...", one entry per bit of `bitmap`. The time is the
/// latest of that fault in `diagnostics`' history (omitted when not there, or no diagnostics).
std::string DescribeFaults(uint32_t bitmap, const protocol::Diagnostics* diagnostics);

}  // namespace palpa::host
