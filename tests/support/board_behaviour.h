// The link behaviour every board is held to through the host library, whatever carries it (the
// Cortex-M image under QEMU, palpa-sim over TCP, a USB gadget through a real kernel's bulk, HID
// and ACM drivers).
#pragma once

#include <cstdint>
#include <string>

#include "palpa/protocol/enums.h"

namespace palpa::testing {

/// Hello with a matching catalog, a configuration change, a setpoint the plant follows in
/// telemetry, and — watched with a bare protocol client over the same device URI — every line
/// safe with host_silence latched once the host goes quiet.
/// `host_timeout_us` is the board's host silence timeout for the check: longer than the board's
/// ticks can be late (a board whose module answers across a slow network).
void CheckBoardBehaviour(const std::string& uri, protocol::BoardKind kind,
                         bool plant_simulated = true, uint32_t host_timeout_us = 150000);

}  // namespace palpa::testing
